#include <fmt/core.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "bouncecal/calibrate/sweep.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "drop_cli_options.h"
#include "option_alias.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

struct SweepCliOptions {
  DropCliOptions drop;
  std::string parameter = "gamma_n";
  std::string values = "0.1:0.9:0.2";
  int first_n = 3;
  std::filesystem::path json;
  std::filesystem::path plot;
};

// The format of --json (docs/json.md).
constexpr const char* kSweepFormat = "bouncecal-sweep/1";

void Plot(const SweepCliOptions& cli, const calibrate::SweepOptions& options,
          const calibrate::SweepSummary& summary) {
  PlotPanel panel{"Simulated energy loss vs " + cli.parameter + " (" +
                      std::string(dem::ToString(cli.drop.LawKind())) +
                      ", h0 = " + fmt::format("{:g}", cli.drop.DropHeightM()) + " m)",
                  cli.parameter + " (1)",
                  "energy loss eta (1)",
                  {},
                  {},
                  {},
                  false,
                  "top left"};
  PlotSeries first{"first impact (simulated)", {}, {}, {}, SeriesStyle::kLinesPoints, false};
  PlotSeries mean{fmt::format("mean of first {} impacts (simulated)", cli.first_n),
                  {},
                  {},
                  {},
                  SeriesStyle::kLinesPoints,
                  true};
  for (const auto& point : summary.points) {
    first.x.push_back(point.value);
    first.y.push_back(point.first_energy_loss);
    mean.x.push_back(point.value);
    mean.y.push_back(point.energy_loss_mean_first_n);
  }
  panel.series = {first, mean};
  if (summary.points.front().analytic_energy_loss) {
    PlotSeries analytic{"closed form, first impact", {}, {}, {}, SeriesStyle::kLines, false};
    const double lo = summary.points.front().value, hi = summary.points.back().value;
    dem::ContactLawConfig law = options.drop.law;
    for (int i = 0; i <= 100; ++i) {
      const double value = lo + (hi - lo) * i / 100.0;
      law.parameters[options.parameter] = value;
      const auto eta =
          calibrate::ClosedFormEnergyLoss(law, options.drop.ball, summary.first_impact_speed_mps);
      if (!eta) continue;
      analytic.x.push_back(value);
      analytic.y.push_back(*eta);
    }
    panel.series.push_back(analytic);
  }
  RenderPlot(cli.plot, {panel});
}

void Run(SweepCliOptions& cli) {
  const TextOutputs text({{"--json", &cli.json}});
  std::FILE* out = text.human();
  if (!cli.plot.empty()) CheckPlotTarget(cli.plot);
  cli.drop.ReadMaterial();
  calibrate::SweepOptions options;
  options.drop = cli.drop.DropSetUp();
  options.parameter = cli.parameter;
  try {
    options.values = calibrate::ParseValueList(cli.values);
  } catch (const ConfigError& error) {
    throw ConfigError(std::string("--values: ") + error.what());
  }
  options.first_n = cli.first_n;
  const auto summary = calibrate::Sweep(options);

  fmt::print(out, "bouncecal sweep: {} {} values, h0 = {:g} m, integrator {}\n",
             options.values.size(), cli.parameter, options.drop.drop_height_m, cli.drop.integrator);
  fmt::print(out, "  {:>10} {:>12} {:>16} {:>12} {:>12} {:>12}\n", cli.parameter, "eta first",
             fmt::format("eta-bar first {}", cli.first_n), "analytic", "first-analytic",
             "time step s");
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& point : summary.points) {
    const std::string analytic =
        point.analytic_energy_loss ? fmt::format("{:.4f}", *point.analytic_energy_loss) : "n/a";
    const std::string difference =
        point.analytic_energy_loss
            ? fmt::format("{:+.4f}", point.first_energy_loss - *point.analytic_energy_loss)
            : "n/a";
    fmt::print(out, "  {:>10.4g} {:>12.4f} {:>16.4f} {:>12} {:>12} {:>12.3g}\n", point.value,
               point.first_energy_loss, point.energy_loss_mean_first_n, analytic, difference,
               point.time_step_s);
    rows.push_back({{"value", point.value},
                    {"first_energy_loss", point.first_energy_loss},
                    {"energy_loss_mean_first_n", point.energy_loss_mean_first_n},
                    {"first_contact_energy_loss", point.first_contact_energy_loss},
                    {"analytic_energy_loss", point.analytic_energy_loss
                                                 ? nlohmann::json(*point.analytic_energy_loss)
                                                 : nlohmann::json(nullptr)},
                    {"impacts", point.impacts},
                    {"time_step_s", point.time_step_s}});
  }
  fmt::print(out, "  ({:.3f} s)\n", summary.time_s);
  if (!cli.json.empty()) {
    WriteTextOutput(cli.json, nlohmann::json{{"format", kSweepFormat},
                                             {"law", dem::ToString(options.drop.law.kind)},
                                             {"contact_law", dem::ToJson(options.drop.law)},
                                             {"parameter", cli.parameter},
                                             {"first_n", cli.first_n},
                                             {"drop_height_m", options.drop.drop_height_m},
                                             {"points", rows}}
                                      .dump(2) +
                                  "\n");
  }
  if (!cli.plot.empty()) {
    Plot(cli, options, summary);
    fmt::print(out, "plot written to {}\n", cli.plot.string());
  }
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  auto cli = std::make_shared<SweepCliOptions>();
  auto* command = app.add_subcommand(
      "sweep",
      "Simulate drops over a range of one law parameter and plot the energy loss against it "
      "(the paper's Fig. 6).");
  command->footer(
      "Example:\n"
      "  bouncecal sweep --law walton-braun --values 0.1:0.9:0.2 --plot sweep.png\n"
      "  bouncecal sweep --material steel.json --parameter stiffness_n_per_m --values "
      "1e6,1e7,1e8 --json -");
  cli->drop.Add(*command, {.law = true, .material = true, .gamma = false});
  auto* values = command->add_option(
      "--values", cli->values,
      "Values of the swept parameter: lo:hi:step or a,b,c (default 0.1:0.9:0.2)");
  AddDeprecatedAlias(*command, values, "--gamma", cli->values);
  command->add_option("--parameter", cli->parameter,
                      "Law parameter to sweep (default gamma_n; unit as its name says)");
  command->add_option("--first", cli->first_n, "Impacts averaged in eta-bar (count, default 3)");
  command->add_option("--json", cli->json,
                      "Write the table as JSON (bouncecal-sweep/1) to this file, - for stdout");
  command->add_option("--plot", cli->plot, "Plot eta vs the parameter (.png or .svg)");
  command->callback([cli] { Run(*cli); });
}

}  // namespace bouncecal::apps
