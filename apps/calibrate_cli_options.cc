#include "calibrate_cli_options.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/calibrate/recording_manifest.h"
#include "bouncecal/error.h"
#include "option_alias.h"

namespace bouncecal::apps {

void CalibrateCliOptions::AddFitOptions(CLI::App& command) {
  auto* recordings = command.add_option(
      "recordings", inputs,
      "Recordings (any audio libsndfile reads), impact-time CSV files "
      "(onset_s[,onset_uncertainty_s[,sequence]]) or bouncecal analyze --json files; several "
      "are fitted jointly");
  auto* manifest_option = command.add_option(
      "--manifest", manifest,
      "CSV or JSON listing the recordings with their drop heights and ball (columns recording, "
      "drop_height_m, drop_height_uncertainty_m, ball; docs/calibration.md), fitted jointly");
  recordings->excludes(manifest_option);
  drop.Add(command, DropCliOptions::Geometry::kAsGiven);
  // One height (or uncertainty) is every recording's: the single-height path of the fit.
  command.parse_complete_callback([this, recordings, manifest_option] {
    if (recordings->count() == 0 && manifest_option->count() == 0) {
      throw ConfigError("give the recordings to fit: their paths, or --manifest FILE");
    }
    if (drop.drop_heights_m.size() == 1) drop.drop_height_m = drop.drop_heights_m.front();
    if (drop_height_uncertainties_m.size() == 1) {
      drop_height_uncertainty_m = drop_height_uncertainties_m.front();
    }
  });
  command
      .add_flag("--unknown-drop-height", unknown_drop_height,
                "The drop height is not known (the default without --drop-height-m)")
      ->group("");
  auto* height_sigma = command.add_option(
      "--drop-height-uncertainty-m", drop_height_uncertainties_m,
      "One-sigma uncertainty of --drop-height-m in m, propagated into e_1 and the confidence "
      "interval (default 0); once for all recordings or once per recording");
  height_sigma->allow_extra_args(false);
  AddDeprecatedAlias(command, height_sigma, "--drop-height-uncertainty",
                     drop_height_uncertainties_m)
      ->allow_extra_args(false);
  command.add_option("--objective", objective,
                     "What the drops must reproduce: mean-energy-loss (eta-bar of the first N "
                     "impacts, the paper's method), intervals (every flight time, weighted) or "
                     "heights (bounce heights)");
  command.add_option(
      "--first", first_n,
      "Impacts averaged by mean-energy-loss (count, default 3, or 2 when a recording "
      "gives only 2, with a warning)");
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
  // One check for a height given once, per recording or in a manifest.
  if (unknown_drop_height && (!drop.drop_heights_m.empty() || !manifest.empty())) {
    throw ConfigError(
        "--unknown-drop-height contradicts the drop heights given (--drop-height-m or "
        "--manifest); give the heights or leave both out");
  }
  // Counts and ranges of per-recording heights, checked before any file is read.
  calibrate::ValidateDropHeights(drop.drop_heights_m, drop_height_uncertainties_m);
  const auto plan =
      calibrate::PlanRecordings(inputs, drop.drop_heights_m, drop_height_uncertainties_m, manifest);
  // The manifest may name the ball; one fit simulates one ball, so it must be one ball.
  std::string manifest_ball;
  for (const auto& entry : plan) {
    if (entry.ball.empty()) continue;
    if (!manifest_ball.empty() && entry.ball != manifest_ball) {
      throw ConfigError(fmt::format(
          "--manifest names two balls ({} and {}); one fit simulates one ball: fit each ball's "
          "recordings with a manifest of their own",
          manifest_ball, entry.ball));
    }
    manifest_ball = entry.ball;
  }
  if (!manifest_ball.empty() && !drop.ball_preset.empty() && manifest_ball != drop.ball_preset) {
    throw ConfigError(fmt::format("--manifest names the ball {} but --ball is {}; give one of them",
                                  manifest_ball, drop.ball_preset));
  }
  if (!manifest_ball.empty() && drop.ball_preset.empty() &&
      (drop.diameter_m || drop.density_kg_per_m3 || drop.mass_kg)) {
    throw ConfigError(fmt::format(
        "--manifest names the ball {} and the command line gives its size or mass too; give one "
        "of them",
        manifest_ball));
  }
  calibrate::FitOptions options;
  options.drop = cli.drop.DropSetUp(validate_law);
  options.ball_given = cli.drop.GivenBall().has_value();
  options.drop_height_given = cli.drop.drop_height_m.has_value();
  options.ball_preset = cli.drop.ball_preset;
  options.contact_duration_s = cli.drop.contact_duration_s;
  if (!manifest_ball.empty() && cli.drop.ball_preset.empty()) {
    options.drop.ball = calibrate::FindBallPreset(manifest_ball).ToBall();
    options.ball_given = true;
    options.ball_preset = manifest_ball;
  }
  options.fitted_parameters = cli.fitted;
  options.objective = calibrate::FitObjectiveFromString(cli.objective);
  if (cli.first_n) {
    options.first_n = *cli.first_n;
    options.first_n_given = true;
  }
  options.max_intervals = cli.max_intervals;
  options.minimizer.local_method = calibrate::LocalMethodFromString(cli.optimizer);
  options.minimizer.max_evaluations = cli.max_evaluations;
  options.minimizer.global_evaluations = cli.global_evaluations;
  options.uncertainty.confidence_level = cli.confidence;
  options.uncertainty.threads = cli.threads;
  options.uncertainty.drop_height_uncertainty_m = cli.drop_height_uncertainty_m;
  // Every setting in range before any input is read (the library names the field, main.cc
  // shows it as its flag).
  options.ValidateSettings();
  return options;
}

calibrate::SequenceInputOptions CalibrateCliOptions::InputOptions() const {
  calibrate::SequenceInputOptions input;
  input.impact_times.default_uncertainty_s = onset_uncertainty_s;
  input.impact_times.Validate();
  return input;
}

bool CalibrateCliOptions::HeightPerRecording() const {
  return !manifest.empty() || drop.drop_heights_m.size() > 1 ||
         drop_height_uncertainties_m.size() > 1;
}

std::vector<std::filesystem::path> CalibrateCliOptions::Recordings() const {
  if (manifest.empty()) return inputs;
  std::vector<std::filesystem::path> recordings;
  for (const auto& entry : calibrate::ReadRecordingManifest(manifest)) {
    recordings.push_back(entry.recording);
  }
  return recordings;
}

std::vector<calibrate::MeasuredSequence> CalibrateCliOptions::LoadSequences() const {
  std::vector<calibrate::MeasuredSequence> sequences;
  if (!HeightPerRecording()) {
    sequences = calibrate::LoadSequences(inputs, InputOptions());
  } else {
    const auto plan = calibrate::PlanRecordings(inputs, drop.drop_heights_m,
                                                drop_height_uncertainties_m, manifest);
    for (const auto& entry : plan) {
      auto read = calibrate::LoadSequences({entry.recording}, InputOptions());
      // Every drop in a recording was released from its height.
      for (auto& sequence : read) {
        sequence.drop_height_m = entry.drop_height_m;
        sequence.drop_height_uncertainty_m = entry.drop_height_uncertainty_m.value_or(0.0);
      }
      sequences.insert(sequences.end(), read.begin(), read.end());
    }
  }
  // Widened, not silent: a lossy file's wider interval is said once per file, as analyze says it.
  std::set<std::filesystem::path> warned;
  for (const auto& sequence : sequences) {
    if (sequence.lossy_codec.empty() || !warned.insert(sequence.path).second) continue;
    fmt::print(stderr,
               "bouncecal: warning: {}: lossy {}: every onset uncertainty not timed from the "
               "impact's response widened by {:.0f} us in quadrature (docs/codecs.md), which "
               "widens the fitted interval; record WAV or FLAC for the full precision\n",
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
