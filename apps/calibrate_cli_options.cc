#include "calibrate_cli_options.h"

#include <fmt/core.h>

#include <filesystem>
#include <set>

#include "bouncecal/error.h"
#include "option_alias.h"

namespace bouncecal::apps {

void CalibrateCliOptions::AddFitOptions(CLI::App& command) {
  command
      .add_option("recordings", inputs,
                  "Recordings (any audio libsndfile reads), impact-time CSV files "
                  "(onset_s[,onset_uncertainty_s[,sequence]]) or bouncecal analyze --json "
                  "files; several are fitted jointly")
      ->required();
  drop.Add(command, DropCliOptions::Geometry::kAsGiven);
  command
      .add_flag("--unknown-drop-height", unknown_drop_height,
                "The drop height is not known (the default without --drop-height-m)")
      ->group("");
  auto* height_sigma = command.add_option(
      "--drop-height-uncertainty-m", drop_height_uncertainty_m,
      "One-sigma uncertainty of --drop-height-m in m, propagated into the confidence interval "
      "(default 0)");
  AddDeprecatedAlias(command, height_sigma, "--drop-height-uncertainty", drop_height_uncertainty_m);
  command.add_option("--objective", objective,
                     "What the drops must reproduce: mean-energy-loss (eta-bar of the first N "
                     "impacts, the paper's method), intervals (every flight time, weighted) or "
                     "heights (bounce heights)");
  command.add_option("--first", first_n, "Impacts averaged by mean-energy-loss (count, default 3)");
  command.add_option("--max-intervals", max_intervals,
                     "Flight intervals per recording fitted by intervals/heights (count, 0: all)");
  command.add_option("--fit", fitted,
                     "Parameter to fit, repeatable (default: the law's damping parameters)");
  command.add_option("--optimizer", optimizer,
                     "NLopt local method: bobyqa, cobyla or nelder-mead (default bobyqa)");
  command.add_option("--max-evaluations", max_evaluations,
                     "Budget of drop simulations for the fit (count, default 200)");
  command.add_option("--global-evaluations", global_evaluations,
                     "DIRECT-L evaluations before the local method (count; -1 automatic: none "
                     "for one parameter under mean-energy-loss, else 12 per parameter)");
  command.add_option("--bootstrap", bootstrap, "No longer used")->group("");
  command.add_option("--seed", seed, "No longer used")->group("");
  command.add_option("--confidence", confidence,
                     "Confidence level of the intervals (fraction, default 0.95)");
  command.add_option("--threads", threads, "Threads for --compare-laws (count, default 2)");
  auto* onset_sigma = command.add_option(
      "--onset-uncertainty-s", onset_uncertainty_s,
      "One-sigma onset uncertainty in s where an input gives none (default 1e-5)");
  AddDeprecatedAlias(command, onset_sigma, "--onset-uncertainty", onset_uncertainty_s);
}

calibrate::FitOptions CalibrateCliOptions::FitOptions(bool validate_law) const {
  const CalibrateCliOptions& cli = *this;
  // The library checks these too, in one sentence for all; here each names its option.
  if (first_n < 1) throw ConfigError(fmt::format("--first must be at least 1, got {}", first_n));
  if (!(confidence > 0 && confidence < 1)) {
    throw ConfigError(fmt::format("--confidence must be in (0, 1), e.g. 0.95, got {}", confidence));
  }
  if (threads < 1) throw ConfigError(fmt::format("--threads must be >= 1, got {}", threads));
  if (!(drop_height_uncertainty_m >= 0)) {
    throw ConfigError(fmt::format("--drop-height-uncertainty-m must be >= 0 m, got {}",
                                  drop_height_uncertainty_m));
  }
  if (unknown_drop_height && drop.drop_height_m) {
    throw ConfigError(
        "--unknown-drop-height contradicts --drop-height-m; give the height or leave both out");
  }
  if (drop_height_uncertainty_m > 0 && !drop.drop_height_m) {
    throw ConfigError(
        "--drop-height-uncertainty-m needs --drop-height-m (without a height nothing depends on "
        "it)");
  }
  if (drop.drop_height_m && !(*drop.drop_height_m > 0 && *drop.drop_height_m < 1e3)) {
    throw ConfigError(
        fmt::format("--drop-height-m must be in (0, 1000) m, got {}", *drop.drop_height_m));
  }
  if (max_evaluations < 1) {
    throw ConfigError(fmt::format("--max-evaluations must be >= 1, got {}", max_evaluations));
  }
  calibrate::FitOptions options;
  options.drop = cli.drop.DropSetUp(validate_law);
  options.ball_given = cli.drop.GivenBall().has_value();
  options.drop_height_given = cli.drop.drop_height_m.has_value();
  options.ball_preset = cli.drop.ball_preset;
  options.fitted_parameters = cli.fitted;
  options.objective = calibrate::FitObjectiveFromString(cli.objective);
  options.first_n = cli.first_n;
  options.max_intervals = cli.max_intervals;
  options.minimizer.local_method = calibrate::LocalMethodFromString(cli.optimizer);
  options.minimizer.max_evaluations = cli.max_evaluations;
  options.minimizer.global_evaluations = cli.global_evaluations;
  options.uncertainty.confidence_level = cli.confidence;
  options.uncertainty.threads = cli.threads;
  options.uncertainty.drop_height_uncertainty_m = cli.drop_height_uncertainty_m;
  return options;
}

calibrate::SequenceInputOptions CalibrateCliOptions::InputOptions() const {
  if (!(onset_uncertainty_s > 0)) {
    throw ConfigError(fmt::format(
        "--onset-uncertainty-s must be a positive number of seconds (e.g. 1e-5), got {}",
        onset_uncertainty_s));
  }
  calibrate::SequenceInputOptions input;
  input.impact_times.default_uncertainty_s = onset_uncertainty_s;
  return input;
}

std::vector<calibrate::MeasuredSequence> CalibrateCliOptions::LoadSequences() const {
  auto sequences = calibrate::LoadSequences(inputs, InputOptions());
  // Widened, not silent: a lossy file's wider interval is said once per file, as analyze says it.
  std::set<std::filesystem::path> warned;
  for (const auto& sequence : sequences) {
    if (sequence.lossy_codec.empty() || !warned.insert(sequence.path).second) continue;
    fmt::print(stderr,
               "bouncecal: warning: {}: lossy {}: every onset uncertainty widened by {:.0f} us "
               "in quadrature (docs/codecs.md), which widens the fitted interval; record WAV or "
               "FLAC for the full precision\n",
               sequence.path.string(), sequence.lossy_codec,
               sequence.codec_timing_uncertainty_s * 1e6);
  }
  return sequences;
}

std::vector<std::string> CalibrateCliOptions::DeprecationWarnings() const {
  std::vector<std::string> warnings;
  if (bootstrap || seed) {
    warnings.push_back(
        "--bootstrap and --seed no longer change anything: the interval now comes from the "
        "impacts' own scatter and the timing noise (docs/calibration.md, uncertainty model), "
        "without random draws; remove them from the command");
  }
  return warnings;
}

}  // namespace bouncecal::apps
