#ifndef BOUNCECAL_APPS_CALIBRATE_NEXT_STEPS_H_
#define BOUNCECAL_APPS_CALIBRATE_NEXT_STEPS_H_

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>

namespace bouncecal::apps {

// What a calibration run had, for the commands it suggests next.
struct CalibrationRun {
  // The calibrate command line as given (recordings and options, outputs left out), shell-quoted.
  std::string arguments;
  std::filesystem::path first_recording;
  std::filesystem::path card;  // empty when no --card was written to a file
  bool ball_given = false;
  std::optional<double> drop_height_m;
};

// The arguments given on `command` (positionals first, then the options in the order the
// command declares them), shell-quoted, without --help and without the options named in `skip`.
std::string GivenArguments(const CLI::App& command, std::initializer_list<std::string> skip);

// The researcher's next commands, ready to paste: write the material card (when this run did
// not), set the measured heights against the card's drop (compare), and write a LAMMPS deck
// (export). Placeholders in capitals stand where the run lacks what a command needs (the ball,
// the drop height), with a note saying so.
std::string NextSteps(const CalibrationRun& run);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CALIBRATE_NEXT_STEPS_H_
