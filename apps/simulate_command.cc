#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/dem/drop.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "drop_cli_options.h"
#include "option_alias.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"
#include "simulate_plot.h"

namespace bouncecal::apps {
namespace {

// The format of --json (docs/json.md, docs/schema/drop.schema.json).
constexpr const char* kDropFormat = "bouncecal-drop/1";

// What the user typed; converted into dem::DropOptions once parsing is done.
struct DropArguments {
  DropCliOptions drop;
  bool allow_unstable_step = false;
  bool classic = false;
  int max_impacts = 1000;
  double max_time_s = 60;
  double rest_flight_s = dem::DropOptions{}.rest_flight_s;
  double rest_contact_factor = dem::DropOptions{}.rest_contact_factor;
  std::filesystem::path json_path;
  std::filesystem::path trajectory_path;
  std::filesystem::path plot_path;
  double trajectory_interval_s = 1e-4;
  bool quiet = false;
};

dem::DropOptions MakeDropOptions(const DropArguments& args) {
  dem::DropOptions options;
  options.law = args.drop.Law(/*validate=*/false);  // SimulateDrop validates it with the ball
  options.ball = args.drop.Ball();
  options.drop_height_m = args.drop.DropHeightM();
  options.gravity_mps2 = args.drop.gravity_mps2;
  options.integrator = args.drop.Integrator();
  if (args.drop.steps_per_contact) options.steps_per_contact = *args.drop.steps_per_contact;
  options.time_step_s = args.drop.time_step_s;
  options.allow_unstable_step = args.allow_unstable_step;
  options.fixed_step_grid = args.drop.fixed_step_grid || args.classic;
  options.locate_contact_events = !args.classic;
  options.drag = args.drop.Drag();
  options.max_impacts = args.max_impacts;
  options.max_time_s = args.max_time_s;
  options.rest_flight_s = args.rest_flight_s;
  options.rest_contact_factor = args.rest_contact_factor;
  options.trajectory_interval_s =
      args.trajectory_path.empty() && args.plot_path.empty() ? 0 : args.trajectory_interval_s;
  return options;
}

nlohmann::json ToJson(const dem::DropResult& result, const dem::DropOptions& options) {
  nlohmann::json impacts = nlohmann::json::array();
  for (const dem::DropImpact& impact : result.impacts) {
    impacts.push_back({{"time_s", impact.time_s},
                       {"restitution", impact.restitution},
                       {"energy_loss", impact.energy_loss},
                       {"contact_duration_s", impact.contact_duration_s},
                       {"max_overlap_m", impact.max_overlap_m},
                       {"speed_in_mps", impact.speed_in_mps},
                       {"speed_out_mps", impact.speed_out_mps},
                       {"released", impact.released}});
  }
  return {{"format", kDropFormat},
          {"impacts", impacts},
          {"stop_reason", std::string(dem::ToString(result.stop_reason))},
          {"stop_detail", result.stop_detail},
          {"steps", result.steps},
          {"time_step_s", result.time_step_s},
          {"stability_limit_s", result.stability_limit_s},
          {"integrator", std::string(dem::ToString(options.integrator))},
          {"contact_law", dem::ToJson(options.law)},
          {"ball",
           {{"diameter_m", options.ball.diameter_m},
            {"density_kg_per_m3", options.ball.DensityKgPerM3()},
            {"mass_kg", options.ball.MassKg()}}},
          {"drop_height_m", options.drop_height_m},
          {"gravity_mps2", options.gravity_mps2}};
}

std::string TrajectoryCsv(const dem::DropResult& result) {
  std::string csv = "time_s,height_m,velocity_mps\n";
  for (const dem::TrajectoryPoint& point : result.trajectory) {
    csv += fmt::format("{:.9g},{:.9g},{:.9g}\n", point.time_s, point.height_m, point.velocity_mps);
  }
  return csv;
}

void PrintSummary(std::FILE* out, const dem::DropResult& result) {
  fmt::print(out, "{:>6} {:>12} {:>11} {:>11} {:>12} {:>14}\n", "impact", "time_s", "restitution",
             "energy_loss", "contact_us", "max_overlap_um");
  for (std::size_t k = 0; k < result.impacts.size(); ++k) {
    const dem::DropImpact& impact = result.impacts[k];
    fmt::print(out, "{:>6} {:>12.6f} {:>11.5f} {:>11.5f} {:>12.3f} {:>14.4f}{}\n", k + 1,
               impact.time_s, impact.restitution, impact.energy_loss,
               impact.contact_duration_s * 1e6, impact.max_overlap_m * 1e6,
               impact.released ? "" : "  (not released)");
  }
  const std::size_t first_n = std::min<std::size_t>(3, result.impacts.size());
  double mean = 0;
  for (std::size_t k = 0; k < first_n; ++k) mean += result.impacts[k].energy_loss;
  if (first_n == 3) fmt::print(out, "mean energy loss of the first 3 impacts: {:.5f}\n", mean / 3);
  fmt::print(out, "stop: {} ({})\n", dem::ToString(result.stop_reason), result.stop_detail);
  fmt::print(out, "steps: {}, time step: {:.4g} s (stability limit {:.4g} s), cpu: {:.3f} ms\n",
             result.steps, result.time_step_s, result.stability_limit_s, result.cpu_s * 1e3);
}

void Run(DropArguments& args) {
  const TextOutputs text({{"--json", &args.json_path}, {"--trajectory", &args.trajectory_path}});
  if (!args.plot_path.empty()) CheckPlotTarget(args.plot_path);
  args.drop.ReadMaterial();
  const dem::DropOptions options = MakeDropOptions(args);
  const dem::DropResult result = dem::SimulateDrop(options);
  if (!args.json_path.empty()) {
    WriteTextOutput(args.json_path, ToJson(result, options).dump(2) + "\n");
  }
  if (!args.trajectory_path.empty()) {
    WriteTextOutput(args.trajectory_path, TrajectoryCsv(result));
  }
  if (!args.quiet) PrintSummary(text.human(), result);
  if (!args.plot_path.empty()) {
    PlotDrop(args.plot_path, result,
             fmt::format("{} law, d = {:g} m, from {:g} m", dem::ToString(options.law.kind),
                         options.ball.diameter_m, options.drop_height_m));
    if (!args.quiet) fmt::print(text.human(), "plot written to {}\n", args.plot_path.string());
  }
}

void AddDropCommand(CLI::App& simulate) {
  auto args = std::make_shared<DropArguments>();
  CLI::App* drop = simulate.add_subcommand(
      "drop", "Simulate a sphere dropped on a rigid plane until it rests (DEM single-ball drop)");
  std::string laws;
  for (dem::ContactLawKind kind : dem::kAllContactLawKinds) {
    std::string names;
    for (const dem::ParameterSpec& spec : dem::ParameterSpecs(kind)) {
      names += fmt::format("{}{} [{}]", names.empty() ? "" : ", ", spec.name, spec.unit);
    }
    laws += fmt::format("\n  {}: {}", dem::ToString(kind), names);
  }
  drop->footer(
      "Examples (the paper's set-up, 1 cm steel ball from 20 cm; a calibrated material card):\n"
      "  bouncecal simulate drop --law walton-braun --gamma 0.5 --stiffness-n-per-m 1e7 "
      "--diameter-m 0.01 --density-kg-per-m3 7800 --drop-height-m 0.2 --json drop.json "
      "--trajectory drop.csv\n"
      "  bouncecal simulate drop --material steel.json --json -\n"
      "Law parameters for --param NAME=VALUE (SI units):" +
      laws);
  args->drop.Add(*drop, {.law = true, .material = true, .gamma = true},
                 DropCliOptions::Geometry::kPaperDefaults);
  drop->add_flag("--allow-unstable-step", args->allow_unstable_step,
                 "Run even if the step exceeds the integrator's stability limit");
  drop->add_flag("--classic", args->classic,
                 "Classic DEM stepping: fixed step grid, forces switch only at step boundaries "
                 "(no located turning point/release)");
  drop->add_option("--max-impacts", args->max_impacts, "Stop after this many impacts (count)")
      ->capture_default_str();
  auto* max_time =
      drop->add_option("--max-time-s", args->max_time_s, "Stop at this simulated time, in s")
          ->capture_default_str();
  AddDeprecatedAlias(*drop, max_time, "--max-time", args->max_time_s);
  auto* rest_flight =
      drop->add_option("--rest-flight-s", args->rest_flight_s,
                       "At rest when a bounce's flight would be shorter than this, in s")
          ->capture_default_str();
  AddDeprecatedAlias(*drop, rest_flight, "--rest-flight", args->rest_flight_s);
  drop->add_option("--rest-contact-factor", args->rest_contact_factor,
                   "At rest when a contact lasts this many contact durations (dimensionless)")
      ->capture_default_str();
  drop->add_option("--json", args->json_path,
                   "Write impacts and summary as JSON (bouncecal-drop/1, docs/json.md) to this "
                   "file, - for stdout");
  drop->add_option("--trajectory", args->trajectory_path,
                   "Write z(t) as CSV (time_s,height_m,velocity_mps) to this file, - for stdout");
  auto* interval = drop->add_option("--trajectory-interval-s", args->trajectory_interval_s,
                                    "Sampling interval of --trajectory, in s")
                       ->capture_default_str();
  AddDeprecatedAlias(*drop, interval, "--trajectory-interval", args->trajectory_interval_s);
  drop->add_option("--plot", args->plot_path,
                   "Plot height vs time with the impacts marked, and eta_k vs k (.png or .svg)");
  drop->add_flag("--quiet", args->quiet, "Do not print the impact table");
  drop->callback([args] { Run(*args); });
}

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  // Other simulations may register under "simulate" too: reuse the group if it exists.
  CLI::App* simulate = nullptr;
  try {
    simulate = app.get_subcommand("simulate");
  } catch (const CLI::OptionNotFound&) {
    simulate = app.add_subcommand("simulate", "Run DEM simulations");
    simulate->require_subcommand(1);
  }
  AddDropCommand(*simulate);
}

}  // namespace bouncecal::apps
