#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>

#include "bouncecal/calibrate/card_creation_time.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/fit_json.h"
#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/error.h"
#include "calibrate_cli_options.h"
#include "calibrate_report.h"
#include "calibration_html.h"
#include "commands.h"
#include "output_target.h"
#include "report_recordings.h"

namespace bouncecal::apps {
namespace {

struct ReportCommandOptions : CalibrateCliOptions {
  std::filesystem::path output;
};

// The options as given, so the page records how to reproduce it.
std::string CommandLine(const CLI::App& command) {
  std::string line = "bouncecal report";
  for (const CLI::Option* option : command.get_options()) {
    // A hidden option (an old spelling) has no name for CLI11's get_name(): its long name is the
    // spelling typed.
    const std::string name =
        option->get_lnames().empty() ? option->get_name() : "--" + option->get_lnames().front();
    if (option->count() == 0 || name == "--help") continue;
    const bool positional = option->get_lnames().empty() && option->get_snames().empty();
    if (option->get_type_size() == 0) {
      line += " " + name;
      continue;
    }
    for (const auto& value : option->results()) {
      line += positional ? " " + value : " " + name + " " + value;
    }
  }
  return line;
}

void Run(const ReportCommandOptions& cli, const std::string& command_line) {
  const TextOutputs text({{"--output", &cli.output}});
  if (!IsStdout(cli.output)) {
    CheckOutputExtension("-o/--output", cli.output, {".html", ".htm"},
                         "the report is one HTML page");
  }
  const std::time_t card_created_at =
      calibrate::CardCreationTimeFromEnvironment(kSourceDateEpochRemedy);
  const auto options = cli.FitOptions();
  calibrate::CheckCardOptions(options);  // the page holds the material card
  for (const auto& warning : cli.DeprecationWarnings())
    fmt::print(stderr, "bouncecal: warning: {}\n", warning);
  const auto sequences = cli.LoadSequences();
  // Before the fit: a recording that cannot be drawn should not cost a fit first.
  RecordingViewOptions view_options;
  view_options.input = cli.InputOptions();
  auto recordings = ViewRecordings(cli.Recordings(), view_options);
  const auto summary = calibrate::Fit(sequences, options);

  CalibrationReportContent content;
  content.command_line = command_line;
  content.summary = summary;
  content.options = options;
  content.recordings = std::move(recordings);
  content.card = calibrate::MakeMaterialCard(summary, options, cli.Recordings(), card_created_at);
  content.card_json = calibrate::ToJson(content.card).dump(2);
  content.fit_json = calibrate::ToJson(summary).dump(2);
  content.figures.emplace_back(
      "Measured (1-sigma bars) and fitted energy loss per impact, and flight times between "
      "impacts.",
      RenderSvgElement(FitPlotPanels(summary)));
  if (const auto gamma_eta = GammaEtaPanel(summary)) {
    PlotOptions square;
    square.width_px = 800;
    square.height_px_per_panel = 520;
    content.figures.emplace_back(
        "Analytic check: the closed-form gamma-eta curve with the measured mean energy loss and "
        "the DEM fit.",
        RenderSvgElement({*gamma_eta}, square));
  }
  WriteTextOutput(cli.output, CalibrationReportHtml(content));
  fmt::print(text.human(), "report written to {} (law {}, {} sequence(s), {} = {:.6g})\n",
             cli.output.string(), dem::ToString(summary.law.kind), sequences.size(),
             summary.parameters.empty() ? std::string("no fitted parameter")
                                        : summary.parameters.front().name,
             summary.parameters.empty() ? 0.0 : summary.parameters.front().value);
}

}  // namespace

void AddReportCommand(CLI::App& app) {
  auto cli = std::make_shared<ReportCommandOptions>();
  auto* command = app.add_subcommand(
      "report",
      "Calibrate like `bouncecal calibrate` and write one self-contained HTML page: inputs with "
      "content hashes, each recording's waveform with every impact, sequence and rejected event "
      "marked, fit summary, analytic check, plots (inline SVG), impacts table and the material "
      "card, for a lab notebook or a paper's supplement.");
  command->footer(
      "Example:\n"
      "  bouncecal report drop1.wav drop2.wav --ball steel-10mm --drop-height-m 0.2 -o "
      "steel.html\n"
      "Takes every fit option of `bouncecal calibrate`; the page uses no script and no external "
      "resource, so it opens offline.");
  cli->AddFitOptions(*command);
  command->add_option("-o,--output", cli->output, "The HTML page to write (.html), - for stdout")
      ->required();
  command->callback([cli, command] { Run(*cli, CommandLine(*command)); });
}

}  // namespace bouncecal::apps
