#ifndef BOUNCECAL_APPS_CALIBRATE_CLI_OPTIONS_H_
#define BOUNCECAL_APPS_CALIBRATE_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "drop_cli_options.h"

namespace bouncecal::apps {

// What a user of the command line does about a SOURCE_DATE_EPOCH the card's time cannot use.
inline constexpr std::string_view kSourceDateEpochRemedy =
    "unset it or set it to e.g. $(git log -1 --format=%ct)";

// The recordings and every fit setting shared by `calibrate` and `report` (outputs are each
// command's own), so both run exactly the same calibration from the same command line.
struct CalibrateCliOptions {
  std::vector<std::filesystem::path> inputs;
  // --manifest: the recordings with their heights (and ball), instead of `inputs`.
  std::filesystem::path manifest;
  DropCliOptions drop;
  // Hidden alias of the default (no --drop-height-m), kept so older scripts still run.
  bool unknown_drop_height = false;
  // Once for every recording, or once per recording; one value is also drop_height_uncertainty_m.
  std::vector<double> drop_height_uncertainties_m;
  double drop_height_uncertainty_m = 0;
  std::string objective = "mean-energy-loss";
  // Unset: FitOptions' default, lowered to what a short recording gives (first_n_given).
  std::optional<int> first_n;
  int max_intervals = 0;
  std::vector<std::string> fitted;
  std::string optimizer = "bobyqa";
  int max_evaluations = 200;
  int global_evaluations = -1;
  // Hidden and ignored: the interval is no longer a bootstrap (DeprecationWarnings names them).
  std::optional<int> bootstrap;
  std::optional<unsigned long long> seed;
  double confidence = 0.95;
  int threads = 2;
  double onset_uncertainty_s = 10e-6;

  // Registers the recordings argument and the fit options on `command`.
  void AddFitOptions(CLI::App& command);
  // Throws ConfigError naming the option and its valid range. --compare-laws passes
  // validate_law = false: its --param values may belong to another law than the default one.
  calibrate::FitOptions FitOptions(bool validate_law = true) const;
  // Validates --onset-uncertainty-s and loads every input through calibrate::LoadSequences. With
  // a height per recording (--drop-height-m repeated, or --manifest) each sequence carries its
  // recording's height; one height for all stays FitOptions' (drop_height_given).
  std::vector<calibrate::MeasuredSequence> LoadSequences() const;
  // The recordings (the inputs, or the manifest's) in order.
  std::vector<std::filesystem::path> Recordings() const;
  // True when the recordings have heights of their own (--drop-height-m given once per
  // recording, or --manifest): the fit then has no single drop height.
  bool HeightPerRecording() const;
  // The options LoadSequences reads the inputs with (ConfigError for a bad
  // --onset-uncertainty-s).
  calibrate::SequenceInputOptions InputOptions() const;
  // One line per option that is accepted for old scripts but no longer does anything, naming
  // what to do instead; empty when none was given.
  std::vector<std::string> DeprecationWarnings() const;
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CALIBRATE_CLI_OPTIONS_H_
