#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/drop.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "plot/gnuplot_plot.h"
#include "simulate_plot.h"

namespace bouncecal::apps {
namespace {

// What the user typed; converted into dem::DropOptions once parsing is done.
struct DropArguments {
  std::string law = "walton-braun";
  double gamma = 0;
  double stiffness_n_per_m = 0;
  double modulus_pa = 0;
  std::vector<std::string> parameters;  // NAME=VALUE
  double diameter_m = 0.01;
  double density_kg_per_m3 = 7800;
  double mass_kg = 0;
  double drop_height_m = 0.2;
  double gravity_mps2 = 9.81;
  double steps_per_contact = dem::DropOptions{}.steps_per_contact;
  double time_step_s = 0;
  std::string integrator = "verlet";
  bool allow_unstable_step = false;
  bool fixed_step_grid = false;
  bool classic = false;
  bool drag = false;
  double drag_coefficient = 0.47;
  double air_density_kg_per_m3 = 1.204;
  int max_impacts = 1000;
  double max_time_s = 60;
  double rest_flight_s = dem::DropOptions{}.rest_flight_s;
  double rest_contact_factor = dem::DropOptions{}.rest_contact_factor;
  std::string json_path;
  std::string trajectory_path;
  std::string plot_path;
  double trajectory_interval_s = 1e-4;
  bool quiet = false;
};

struct DropOptionHandles {
  CLI::Option* gamma = nullptr;
  CLI::Option* stiffness = nullptr;
  CLI::Option* modulus = nullptr;
  CLI::Option* mass = nullptr;
  CLI::Option* dt = nullptr;
};

double ParseNumber(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty()) {
    throw ConfigError(fmt::format("{}: '{}' is not a number", what, text));
  }
  return value;
}

// The law's parameter that a convenience option sets, by law.
void SetLawParameter(dem::ContactLawConfig& config, const std::string& option,
                     const std::map<dem::ContactLawKind, std::string_view>& names, double value) {
  const auto found = names.find(config.kind);
  if (found == names.end()) {
    throw ConfigError(
        fmt::format("{} does not apply to the {} law; set its parameters with --param NAME=VALUE",
                    option, dem::ToString(config.kind)));
  }
  config.parameters[std::string(found->second)] = value;
}

dem::DropOptions MakeDropOptions(const DropArguments& args, const DropOptionHandles& handles) {
  dem::DropOptions options;
  options.law.kind = dem::ContactLawKindFromString(args.law);
  using dem::ContactLawKind;
  if (handles.gamma->count() > 0) {
    SetLawParameter(options.law, "--gamma",
                    {{ContactLawKind::kWaltonBraun, "gamma_n"},
                     {ContactLawKind::kLinearDashpot, "damping_ratio"}},
                    args.gamma);
  }
  if (handles.stiffness->count() > 0) {
    SetLawParameter(options.law, "--stiffness",
                    {{ContactLawKind::kWaltonBraun, "stiffness_n_per_m"},
                     {ContactLawKind::kWaltonBraunPlastic, "stiffness_n_per_m"},
                     {ContactLawKind::kLinearDashpot, "stiffness_n_per_m"}},
                    args.stiffness_n_per_m);
  }
  if (handles.modulus->count() > 0) {
    SetLawParameter(options.law, "--modulus",
                    {{ContactLawKind::kHertz, "effective_modulus_pa"},
                     {ContactLawKind::kHertzViscoelastic, "effective_modulus_pa"}},
                    args.modulus_pa);
  }
  for (const std::string& assignment : args.parameters) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos) {
      throw ConfigError(
          fmt::format("--param '{}' must look like NAME=VALUE, e.g. gamma_n=0.4", assignment));
    }
    const std::string name = assignment.substr(0, equals);
    options.law.parameters[name] = ParseNumber(assignment.substr(equals + 1), "--param " + name);
  }
  options.ball.diameter_m = args.diameter_m;
  options.ball.density_kg_per_m3 = args.density_kg_per_m3;
  if (handles.mass->count() > 0) options.ball.mass_kg = args.mass_kg;
  options.drop_height_m = args.drop_height_m;
  options.gravity_mps2 = args.gravity_mps2;
  options.integrator = dem::IntegratorFromString(args.integrator);
  options.steps_per_contact = args.steps_per_contact;
  if (handles.dt->count() > 0) options.time_step_s = args.time_step_s;
  options.allow_unstable_step = args.allow_unstable_step;
  options.fixed_step_grid = args.fixed_step_grid || args.classic;
  options.locate_contact_events = !args.classic;
  options.drag = {.enabled = args.drag,
                  .drag_coefficient = args.drag_coefficient,
                  .air_density_kg_per_m3 = args.air_density_kg_per_m3};
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
  return {{"impacts", impacts},
          {"stop_reason", std::string(dem::ToString(result.stop_reason))},
          {"stop_detail", result.stop_detail},
          {"steps", result.steps},
          {"time_step_s", result.time_step_s},
          {"stability_limit_s", result.stability_limit_s},
          {"integrator", std::string(dem::ToString(options.integrator))},
          {"contact_law", dem::ToJson(options.law)},
          {"ball",
           {{"diameter_m", options.ball.diameter_m},
            {"density_kg_per_m3", options.ball.density_kg_per_m3},
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

void PrintSummary(const dem::DropResult& result) {
  fmt::print("{:>6} {:>12} {:>11} {:>11} {:>12} {:>14}\n", "impact", "time_s", "restitution",
             "energy_loss", "contact_us", "max_overlap_um");
  for (std::size_t k = 0; k < result.impacts.size(); ++k) {
    const dem::DropImpact& impact = result.impacts[k];
    fmt::print("{:>6} {:>12.6f} {:>11.5f} {:>11.5f} {:>12.3f} {:>14.4f}{}\n", k + 1, impact.time_s,
               impact.restitution, impact.energy_loss, impact.contact_duration_s * 1e6,
               impact.max_overlap_m * 1e6, impact.released ? "" : "  (not released)");
  }
  const std::size_t first_n = std::min<std::size_t>(3, result.impacts.size());
  double mean = 0;
  for (std::size_t k = 0; k < first_n; ++k) mean += result.impacts[k].energy_loss;
  if (first_n == 3) fmt::print("mean energy loss of the first 3 impacts: {:.5f}\n", mean / 3);
  fmt::print("stop: {} ({})\n", dem::ToString(result.stop_reason), result.stop_detail);
  fmt::print("steps: {}, time step: {:.4g} s (stability limit {:.4g} s), cpu: {:.3f} ms\n",
             result.steps, result.time_step_s, result.stability_limit_s, result.cpu_s * 1e3);
}

void AddDropCommand(CLI::App& simulate) {
  auto args = std::make_shared<DropArguments>();
  auto handles = std::make_shared<DropOptionHandles>();
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
      "Example (the paper's set-up, 1 cm steel ball from 20 cm):\n"
      "  bouncecal simulate drop --law walton-braun --gamma 0.5 --stiffness 1e7 --diameter 0.01 "
      "--density 7800 --drop-height 0.2 --json drop.json --trajectory drop.csv\n"
      "Law parameters for --param NAME=VALUE (SI units):" +
      laws);
  drop->add_option("--law", args->law, "Contact law: " + dem::ContactLawNames())
      ->capture_default_str();
  handles->gamma = drop->add_option(
      "--gamma", args->gamma,
      "Damping (dimensionless): gamma_n of walton-braun, damping_ratio of linear-dashpot");
  handles->stiffness =
      drop->add_option("--stiffness", args->stiffness_n_per_m,
                       "Normal (loading) stiffness in N/m for the linear laws (default 1e7)");
  handles->modulus =
      drop->add_option("--modulus", args->modulus_pa,
                       "Effective modulus E* in Pa for the Hertz laws (default 1.1e11)");
  drop->add_option("--param", args->parameters,
                   "Any law parameter as NAME=VALUE in its SI unit, e.g. "
                   "unloading_stiffness_n_per_m=3e7 (repeatable)");
  drop->add_option("--diameter", args->diameter_m, "Ball diameter in m")->capture_default_str();
  drop->add_option("--density", args->density_kg_per_m3, "Ball density in kg/m^3")
      ->capture_default_str();
  handles->mass =
      drop->add_option("--mass", args->mass_kg, "Ball mass in kg (overrides --density)");
  drop->add_option("--drop-height", args->drop_height_m,
                   "Release gap between the ball's lowest point and the plane, in m")
      ->capture_default_str();
  drop->add_option("--gravity", args->gravity_mps2, "Gravity in m/s^2")->capture_default_str();
  drop->add_option("--integrator", args->integrator,
                   "Contact integrator: " + dem::IntegratorNames() +
                       " (exact: closed form, linear laws only)")
      ->capture_default_str();
  drop->add_option("--steps-per-contact", args->steps_per_contact,
                   "Time steps per contact duration (dimensionless)")
      ->capture_default_str();
  handles->dt = drop->add_option("--dt", args->time_step_s,
                                 "Absolute time step in s (overrides --steps-per-contact)");
  drop->add_flag("--allow-unstable-step", args->allow_unstable_step,
                 "Run even if the step exceeds the integrator's stability limit");
  drop->add_flag("--fixed-step-grid", args->fixed_step_grid,
                 "One step grid from release; contacts start at the first step with overlap");
  drop->add_flag("--classic", args->classic,
                 "Classic DEM stepping: fixed step grid, forces switch only at step boundaries "
                 "(no located turning point/release)");
  drop->add_flag("--drag", args->drag, "Enable quadratic air drag");
  drop->add_option("--drag-coefficient", args->drag_coefficient,
                   "Drag coefficient C_d (dimensionless)")
      ->capture_default_str();
  drop->add_option("--air-density", args->air_density_kg_per_m3, "Air density in kg/m^3")
      ->capture_default_str();
  drop->add_option("--max-impacts", args->max_impacts, "Stop after this many impacts")
      ->capture_default_str();
  drop->add_option("--max-time", args->max_time_s, "Stop at this simulated time, in s")
      ->capture_default_str();
  drop->add_option("--rest-flight", args->rest_flight_s,
                   "At rest when a bounce's flight would be shorter than this, in s")
      ->capture_default_str();
  drop->add_option("--rest-contact-factor", args->rest_contact_factor,
                   "At rest when a contact lasts this many contact durations (dimensionless)")
      ->capture_default_str();
  drop->add_option("--json", args->json_path, "Write impacts and summary as JSON to FILE");
  drop->add_option("--trajectory", args->trajectory_path,
                   "Write z(t) as CSV (time_s,height_m,velocity_mps) to FILE");
  drop->add_option("--trajectory-interval", args->trajectory_interval_s,
                   "Sampling interval of --trajectory, in s")
      ->capture_default_str();
  drop->add_option("--plot", args->plot_path,
                   "Plot height vs time with the impacts marked, and eta_k vs k (.png or .svg)");
  drop->add_flag("--quiet", args->quiet, "Do not print the impact table");
  drop->callback([args, handles] {
    if (!args->plot_path.empty()) CheckPlotTarget(args->plot_path);
    const dem::DropOptions options = MakeDropOptions(*args, *handles);
    const dem::DropResult result = dem::SimulateDrop(options);
    if (!args->json_path.empty()) {
      WriteFileAtomically(args->json_path, ToJson(result, options).dump(2) + "\n");
    }
    if (!args->trajectory_path.empty()) {
      WriteFileAtomically(args->trajectory_path, TrajectoryCsv(result));
    }
    if (!args->quiet) PrintSummary(result);
    if (!args->plot_path.empty()) {
      PlotDrop(args->plot_path, result,
               fmt::format("{} law, d = {:g} m, from {:g} m", dem::ToString(options.law.kind),
                           options.ball.diameter_m, options.drop_height_m));
      if (!args->quiet) fmt::print("plot written to {}\n", args->plot_path);
    }
  });
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
