#include "stop_signals.h"

#include <unistd.h>

#include "exit_codes.h"

namespace bouncecal::apps {
namespace {

// The one piece of global mutable state in the program, and unavoidable: a signal handler
// receives no argument through which to reach an object, and the only thing it may portably
// write is a volatile sig_atomic_t. The run polls it once per step through
// StopSignals::requested().
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void OnStopSignal(int signal) {
  if (stop_signal != 0) {
    // Only async-signal-safe calls here: write(2) and _exit(2).
    constexpr char kMessage[] =
        "\nbouncecal: second signal: stopped at once; the last checkpoint written stays valid\n";
    [[maybe_unused]] const auto ignored = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
    ::_exit(kExitInterrupted);
  }
  stop_signal = signal;
}

}  // namespace

StopSignals::StopSignals() {
  stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
}

bool StopSignals::requested() const { return stop_signal != 0; }

int StopSignals::signal() const { return stop_signal; }

}  // namespace bouncecal::apps
