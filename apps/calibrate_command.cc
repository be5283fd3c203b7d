#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bouncecal/calibrate/card_creation_time.h"
#include "bouncecal/calibrate/contact_stiffness.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/fit_json.h"
#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "calibrate_cli_options.h"
#include "calibrate_next_steps.h"
#include "calibrate_report.h"
#include "commands.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

struct CalibrateCommandOptions : CalibrateCliOptions {
  bool compare_laws = false;
  bool objective_given = false;  // --objective typed: --compare-laws keeps it even with no dof
  std::vector<std::string> laws;
  std::filesystem::path json;
  std::filesystem::path card;
  std::filesystem::path plot;
};

void Run(const CalibrateCommandOptions& cli, const CLI::App& command) {
  const TextOutputs text({{"--json", &cli.json}, {"--card", &cli.card}});
  std::FILE* out = text.human();
  if (!cli.plot.empty()) CheckPlotTarget(cli.plot);
  // Read before the fit so a malformed SOURCE_DATE_EPOCH fails at once, not after minutes.
  const std::time_t card_created_at =
      calibrate::CardCreationTimeFromEnvironment(kSourceDateEpochRemedy);
  auto options = cli.FitOptions(/*validate_law=*/!cli.compare_laws);
  // A card needs the ball: refuse before the (possibly long) fit rather than after it.
  if (!cli.card.empty()) calibrate::CheckCardOptions(options);
  for (const auto& warning : cli.DeprecationWarnings())
    fmt::print(stderr, "bouncecal: warning: {}\n", warning);
  const auto sequences = cli.LoadSequences();
  const auto write_card = [&](const calibrate::FitSummary& fit) {
    const auto card = calibrate::MakeMaterialCard(fit, options, cli.Recordings(), card_created_at);
    WriteTextOutput(cli.card, calibrate::ToJson(card).dump(2) + "\n");
  };
  const auto print_next_steps = [&] {
    const CalibrationRun run{GivenArguments(command, {"--json", "--card", "--plot"}),
                             cli.Recordings().front(),
                             IsStdout(cli.card) ? std::filesystem::path() : cli.card,
                             options.ball_given, options.GivenDropHeightM()};
    fmt::print(out, "{}", NextSteps(run));
  };

  if (cli.compare_laws) {
    std::vector<dem::ContactLawKind> kinds;
    if (cli.laws.empty()) {
      kinds.assign(dem::kAllContactLawKinds.begin(), dem::kAllContactLawKinds.end());
    } else {
      for (const auto& name : cli.laws) kinds.push_back(dem::ContactLawKindFromString(name));
    }
    const auto comparison = calibrate::CompareLaws(sequences, kinds, options, cli.objective_given);
    PrintComparison(out, comparison, sequences.size());
    if (!cli.json.empty()) WriteTextOutput(cli.json, ToJson(comparison).dump(2) + "\n");
    if (!cli.plot.empty()) PlotFit(cli.plot, comparison.fits.front());
    if (!cli.card.empty()) {
      write_card(comparison.fits.front());
      fmt::print(out, "material card of the best law written to {}\n", cli.card.string());
    }
    print_next_steps();
    return;
  }

  const auto summary = calibrate::Fit(sequences, options);
  PrintFit(out, summary, options, sequences.size());
  if (!cli.json.empty()) {
    WriteTextOutput(cli.json, calibrate::ToJson(summary).dump(2) + "\n");
    fmt::print(out, "JSON written to {}\n", cli.json.string());
  }
  if (!cli.card.empty()) {
    write_card(summary);
    fmt::print(out, "material card written to {}\n", cli.card.string());
  }
  if (!cli.plot.empty()) {
    PlotFit(cli.plot, summary);
    fmt::print(out, "plot written to {}\n", cli.plot.string());
  }
  print_next_steps();
}

}  // namespace

void AddCalibrateCommand(CLI::App& app) {
  auto cli = std::make_shared<CalibrateCommandOptions>();
  auto* command = app.add_subcommand(
      "calibrate",
      "Fit the contact damping so single-ball DEM drops lose the energy the recordings show.");
  command->footer(
      "Example:\n"
      "  bouncecal calibrate drop1.wav drop2.wav --ball steel-10mm --drop-height-m 0.2 --card "
      "steel.json\n"
      "  bouncecal calibrate drop.wav --ball tennis --objective intervals --compare-laws --plot "
      "fit.png");
  cli->AddFitOptions(*command);
  command->add_flag("--compare-laws", cli->compare_laws,
                    "Fit several laws to the same recordings and rank them by BIC");
  command
      ->add_option("--laws", cli->laws,
                   "Laws for --compare-laws (default: every law with a damping parameter)")
      ->delimiter(',');
  command->add_option("--json", cli->json,
                      "Write the full result as JSON (bouncecal-fit/1, or "
                      "bouncecal-law-comparison/1 with --compare-laws) to this file, - for stdout");
  command->add_option("--card", cli->card,
                      "Write the calibrated material card (JSON, bouncecal-material/1) to this "
                      "file, - for stdout");
  command->add_option("--plot", cli->plot,
                      "Plot measured vs fitted energy loss and flight times (.png or .svg)");
  command->callback([cli, command] {
    cli->objective_given = command->count("--objective") > 0;
    Run(*cli, *command);
  });
}

}  // namespace bouncecal::apps
