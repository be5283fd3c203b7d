#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/fit_json.h"
#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/dem/contact_law_kind.h"
#include "bouncecal/error.h"
#include "calibrate_report.h"
#include "commands.h"
#include "drop_cli_options.h"

namespace bouncecal::apps {
namespace {

struct CalibrateCliOptions {
  std::vector<std::filesystem::path> inputs;
  DropCliOptions drop;
  bool unknown_drop_height = false;
  double drop_height_uncertainty_m = 0;
  std::string objective = "mean-energy-loss";
  int first_n = 3;
  int max_intervals = 0;
  std::vector<std::string> fitted;
  bool compare_laws = false;
  std::vector<std::string> laws;
  std::string optimizer = "bobyqa";
  int max_evaluations = 200;
  int global_evaluations = -1;
  int bootstrap = 32;
  double confidence = 0.95;
  unsigned long long seed = 1;
  int threads = 2;
  double onset_uncertainty_s = 10e-6;
  std::filesystem::path json;
  std::filesystem::path card;
  std::filesystem::path plot;
};

calibrate::FitOptions ToFitOptions(const CalibrateCliOptions& cli) {
  calibrate::FitOptions options;
  options.law = cli.drop.Law(/*validate=*/!cli.compare_laws);
  options.fitted_parameters = cli.fitted;
  options.ball = cli.drop.Ball();
  options.drop_height_m =
      cli.unknown_drop_height ? std::nullopt : std::optional<double>(cli.drop.drop_height_m);
  options.gravity_mps2 = cli.drop.gravity_mps2;
  options.drag = cli.drop.Drag();
  options.integrator = cli.drop.Integrator();
  options.time_step_s = cli.drop.time_step_s;
  options.steps_per_contact = cli.drop.steps_per_contact;
  options.fixed_step_grid = cli.drop.fixed_step_grid;
  options.objective = calibrate::FitObjectiveFromString(cli.objective);
  options.first_n = cli.first_n;
  options.max_intervals = cli.max_intervals;
  options.minimizer.local_method = calibrate::LocalMethodFromString(cli.optimizer);
  options.minimizer.max_evaluations = cli.max_evaluations;
  options.minimizer.global_evaluations = cli.global_evaluations;
  options.uncertainty.bootstrap_samples = cli.bootstrap;
  options.uncertainty.confidence_level = cli.confidence;
  options.uncertainty.seed = cli.seed;
  options.uncertainty.threads = cli.threads;
  options.uncertainty.drop_height_uncertainty_m = cli.drop_height_uncertainty_m;
  return options;
}

void Run(const CalibrateCliOptions& cli) {
  const auto options = ToFitOptions(cli);
  if (!(cli.onset_uncertainty_s > 0)) {
    throw ConfigError("--onset-uncertainty must be a positive number of seconds");
  }
  calibrate::SequenceInputOptions input;
  input.impact_times.default_uncertainty_s = cli.onset_uncertainty_s;
  const auto sequences = calibrate::LoadSequences(cli.inputs, input);

  if (cli.compare_laws) {
    std::vector<dem::ContactLawKind> kinds;
    if (cli.laws.empty()) {
      kinds.assign(dem::kAllContactLawKinds.begin(), dem::kAllContactLawKinds.end());
    } else {
      for (const auto& name : cli.laws) kinds.push_back(dem::ContactLawKindFromString(name));
    }
    const auto comparison = calibrate::CompareLaws(sequences, kinds, options);
    PrintComparison(comparison, sequences.size());
    if (!cli.json.empty()) WriteFileAtomically(cli.json, ToJson(comparison).dump(2) + "\n");
    if (!cli.plot.empty()) PlotFit(cli.plot, comparison.fits.front(), options);
    if (!cli.card.empty()) {
      calibrate::WriteMaterialCard(
          cli.card, calibrate::MakeMaterialCard(comparison.fits.front(), options, cli.inputs));
      fmt::print("material card of the best law written to {}\n", cli.card.string());
    }
    return;
  }

  const auto summary = calibrate::Fit(sequences, options);
  PrintFit(summary, options, sequences.size());
  if (!cli.json.empty()) {
    WriteFileAtomically(cli.json, calibrate::ToJson(summary).dump(2) + "\n");
    fmt::print("JSON written to {}\n", cli.json.string());
  }
  if (!cli.card.empty()) {
    calibrate::WriteMaterialCard(cli.card,
                                 calibrate::MakeMaterialCard(summary, options, cli.inputs));
    fmt::print("material card written to {}\n", cli.card.string());
  }
  if (!cli.plot.empty()) {
    PlotFit(cli.plot, summary, options);
    fmt::print("plot written to {}\n", cli.plot.string());
  }
}

}  // namespace

void AddCalibrateCommand(CLI::App& app) {
  auto cli = std::make_shared<CalibrateCliOptions>();
  auto* command = app.add_subcommand(
      "calibrate",
      "Fit the contact damping so single-ball DEM drops lose the energy the recordings show.\n"
      "Example: bouncecal calibrate drop1.wav drop2.wav --drop-height 0.2 --card steel.json\n"
      "         bouncecal calibrate drop.wav --objective intervals --compare-laws --plot fit.png");
  command
      ->add_option("recordings", cli->inputs,
                   "Recordings (any audio libsndfile reads), impact-time CSV files "
                   "(onset_s[,onset_uncertainty_s[,sequence]]) or bouncecal analyze --json "
                   "files; several are fitted jointly")
      ->required();
  cli->drop.Add(*command);
  command->add_flag("--unknown-drop-height", cli->unknown_drop_height,
                    "The drop height is not known: simulations start from the apex of the first "
                    "measured flight");
  command->add_option("--drop-height-uncertainty", cli->drop_height_uncertainty_m,
                      "One-sigma uncertainty of --drop-height in m, propagated into the "
                      "confidence interval (default 0)");
  command->add_option("--objective", cli->objective,
                      "What the drops must reproduce: mean-energy-loss (eta-bar of the first N "
                      "impacts, the paper's method), intervals (every flight time, weighted) or "
                      "heights (bounce heights)");
  command->add_option("--first", cli->first_n,
                      "Impacts averaged by mean-energy-loss (count, default 3)");
  command->add_option("--max-intervals", cli->max_intervals,
                      "Flight intervals per recording fitted by intervals/heights (count, 0: all)");
  command->add_option("--fit", cli->fitted,
                      "Parameter to fit, repeatable (default: the law's damping parameters)");
  command->add_flag("--compare-laws", cli->compare_laws,
                    "Fit several laws to the same recordings and rank them by BIC");
  command
      ->add_option("--laws", cli->laws,
                   "Laws for --compare-laws (default: every law with a damping parameter)")
      ->delimiter(',');
  command->add_option("--optimizer", cli->optimizer,
                      "NLopt local method: bobyqa, cobyla or nelder-mead (default bobyqa)");
  command->add_option("--max-evaluations", cli->max_evaluations,
                      "Budget of drop simulations for the fit (count, default 200)");
  command->add_option("--global-evaluations", cli->global_evaluations,
                      "DIRECT-L evaluations before the local method (count; -1 automatic: none "
                      "for one parameter under mean-energy-loss, else 12 per parameter)");
  command->add_option("--bootstrap", cli->bootstrap,
                      "Bootstrap refits for the confidence intervals (count, 0 skips, default 32)");
  command->add_option("--confidence", cli->confidence,
                      "Confidence level of the intervals (fraction, default 0.95)");
  command->add_option("--seed", cli->seed, "Random seed of the bootstrap (integer, default 1)");
  command->add_option("--threads", cli->threads, "Threads for the bootstrap (count, default 2)");
  command->add_option("--onset-uncertainty", cli->onset_uncertainty_s,
                      "One-sigma onset uncertainty in s where an input gives none (default 1e-5)");
  command->add_option("--json", cli->json, "Write the full result as JSON to this file");
  command->add_option("--card", cli->card,
                      "Write the calibrated material card (JSON) to this file");
  command->add_option("--plot", cli->plot,
                      "Plot measured vs fitted energy loss and flight times (.png or .svg)");
  command->callback([cli] { Run(*cli); });
}

}  // namespace bouncecal::apps
