#include <fmt/core.h>

#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/calibrate/sweep.h"
#include "bouncecal/calibrate/trajectory_compare.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "drop_cli_options.h"
#include "option_alias.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

struct CompareCliOptions {
  std::filesystem::path input;
  DropCliOptions drop;
  std::string gamma_values;
  double sample_interval_s = 5e-4;
  std::filesystem::path json;
  std::filesystem::path plot;
};

// The format of --json (docs/json.md).
constexpr const char* kCompareFormat = "bouncecal-trajectory-comparison/1";

// The law and its set parameters other than the elastic ones (which set only the contact time).
std::string Label(const dem::ContactLawConfig& law) {
  std::string text(dem::ToString(law.kind));
  for (const auto& [name, value] : law.parameters) {
    const auto specs = dem::ParameterSpecs(law.kind);
    const bool elastic = std::any_of(specs.begin(), specs.end(), [&](const auto& spec) {
      return spec.name == name && spec.role == dem::ParameterRole::kElastic;
    });
    if (!elastic) text += fmt::format(" {}={:.4g}", name, value);
  }
  return text;
}

void Run(CompareCliOptions& cli) {
  const TextOutputs text({{"--json", &cli.json}});
  std::FILE* out = text.human();
  if (!cli.plot.empty()) CheckPlotTarget(cli.plot);
  if (cli.gamma_values.empty() == cli.drop.material.empty()) {
    throw ConfigError("give exactly one of --gamma LIST or --material CARD");
  }
  cli.drop.ReadMaterial();
  // The simulated drops start at the release height, and the measured arcs are set against
  // them: an assumed height (the paper's) would be a silent wrong answer. A card's height is the
  // one its recordings were fitted at, and is used.
  if (cli.drop.DropHeightSource() == "default") {
    throw ConfigError(
        cli.drop.card()
            ? "compare needs a drop height: the card " + cli.drop.material.string() +
                  " was fitted from the first bounce's apex (no drop height recorded); give "
                  "--drop-height-m (the height the ball was released from, m)"
            : std::string("compare needs --drop-height-m (the height the ball was released from, "
                          "m) to simulate the drop the recording shows, or a --material card "
                          "fitted with one; without it, fit the recording with bouncecal "
                          "calibrate"));
  }
  calibrate::TrajectoryCompareOptions options;
  options.drop = cli.drop.DropSetUp();
  if (!cli.drop.material.empty()) {
    options.laws.push_back(cli.drop.Law());
  } else {
    for (double gamma : calibrate::ParseValueList(cli.gamma_values)) {
      auto law = cli.drop.Law();
      law.parameters["gamma_n"] = gamma;
      law.Validate();
      options.laws.push_back(law);
    }
  }
  options.sample_interval_s = cli.sample_interval_s;
  const auto sequences = calibrate::LoadSequences({cli.input});
  std::vector<double> onsets;
  for (const auto& impact : sequences.front().impacts) onsets.push_back(impact.onset_s);
  const auto summary = calibrate::CompareTrajectories(onsets, options);

  fmt::print(out,
             "bouncecal compare: {} ({} impacts), h0 = {:g} m (from the {}); measured arcs vs "
             "simulated drops\n",
             sequences.front().source, onsets.size(), options.drop.drop_height_m,
             cli.drop.DropHeightSource());
  fmt::print(out, "  ball: d = {:g} m, m = {:.6g} kg{}\n", options.drop.ball.diameter_m,
             options.drop.ball.MassKg(),
             cli.drop.card()         ? " (from the card)"
             : !cli.drop.GivenBall() ? " (no --ball given: the paper's 1 cm steel ball; "
                                       "walton-braun's heights do not depend on it)"
                                     : " (from the command line)");
  const bool drag = options.drop.drag.enabled;
  const std::string_view drag_source = cli.drop.DragSource();
  fmt::print(out, "  drag {} ({})\n", drag ? "on" : "off",
             drag_source == "card"           ? "from the card"
             : drag_source == "command line" ? (drag ? "--drag" : "--no-drag")
                                             : "the default; --drag switches it on");
  fmt::print(out, "  {:<40} {:>18}\n", "simulated law", "RMS height error m");
  nlohmann::json curves = nlohmann::json::array();
  for (const auto& curve : summary.simulated) {
    fmt::print(out, "  {:<40} {:>18.5f}\n", Label(curve.law), curve.rms_height_error_m);
    curves.push_back({{"contact_law", dem::ToJson(curve.law)},
                      {"rms_height_error_m", curve.rms_height_error_m}});
  }
  if (!cli.json.empty()) {
    WriteTextOutput(cli.json, nlohmann::json{{"format", kCompareFormat},
                                             {"source", sequences.front().source},
                                             {"drop_height_m", options.drop.drop_height_m},
                                             {"drop_height_source", cli.drop.DropHeightSource()},
                                             {"drag", drag},
                                             {"drag_source", drag_source},
                                             {"curves", curves}}
                                      .dump(2) +
                                  "\n");
  }
  if (!cli.plot.empty()) {
    PlotPanel panel{"Bounce trajectory: measured (arcs from the onsets) vs simulated",
                    "time since release t (s)",
                    "height of the ball's lowest point h (m)",
                    {},
                    {},
                    {},
                    false,
                    "top right"};
    panel.series.push_back({"measured " + sequences.front().source,
                            summary.measured.time_s,
                            summary.measured.height_m,
                            {},
                            SeriesStyle::kLines,
                            false});
    for (const auto& curve : summary.simulated) {
      panel.series.push_back(
          {fmt::format("{} (RMS {:.4f} m)", Label(curve.law), curve.rms_height_error_m),
           curve.curve.time_s,
           curve.curve.height_m,
           {},
           SeriesStyle::kLines,
           true});
    }
    RenderPlot(cli.plot, {panel});
    fmt::print(out, "plot written to {}\n", cli.plot.string());
  }
}

}  // namespace

void AddCompareCommand(CLI::App& app) {
  auto cli = std::make_shared<CompareCliOptions>();
  auto* command = app.add_subcommand(
      "compare",
      "Plot the measured bounce trajectory against simulated drops, with the RMS height error "
      "per curve (the paper's Fig. 5).");
  command->footer(
      "Example:\n"
      "  bouncecal compare drop.wav --gamma 0.1,0.3,0.5,0.7,0.9 --plot fig5.png");
  command
      ->add_option("recording", cli->input,
                   "Recording, impact-time CSV or analyze JSON (its first bounce sequence)")
      ->required();
  cli->drop.Add(*command, {.law = true, .material = true, .gamma = false});
  command->add_option("--gamma", cli->gamma_values,
                      "gamma_n values to simulate: a,b,c or lo:hi:step (walton-braun), or give "
                      "--material");
  auto* sample = command->add_option("--sample-interval-s", cli->sample_interval_s,
                                     "Spacing of the height samples in s (default 5e-4)");
  AddDeprecatedAlias(*command, sample, "--sample-interval", cli->sample_interval_s);
  command->add_option("--json", cli->json,
                      "Write the RMS errors as JSON (bouncecal-trajectory-comparison/1) to this "
                      "file, - for stdout");
  command->add_option("--plot", cli->plot, "Plot height vs time (.png or .svg)");
  command->callback([cli] { Run(*cli); });
}

}  // namespace bouncecal::apps
