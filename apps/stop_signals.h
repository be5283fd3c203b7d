#ifndef BOUNCECAL_APPS_STOP_SIGNALS_H_
#define BOUNCECAL_APPS_STOP_SIGNALS_H_

#include <csignal>

#include "bouncecal/error.h"

namespace bouncecal::apps {

// A long run stopped on request (SIGINT/SIGTERM) after saving what it needs to go on; the
// message says how to resume (exit status kExitInterrupted).
class InterruptedError : public Error {
 public:
  using Error::Error;
};

// SIGINT and SIGTERM while a long command runs (docs/scenes.md, "Checkpoints"): the first asks
// the run to stop at its next safe point, where it saves a checkpoint and its summary; a second
// ends the process at once with kExitInterrupted. Outputs are written through AtomicFile, so
// ending at once leaves whole files or none (a temporary *.tmp.<pid> at most, which the next run
// in that folder removes). One instance at a time; the previous handlers come back on
// destruction.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  bool requested() const;
  // The signal that asked to stop (SIGINT or SIGTERM), 0 when none did.
  int signal() const;

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_STOP_SIGNALS_H_
