#include "drop_cli_options.h"

#include <cmath>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/dem/contact_law_kind.h"
#include "bouncecal/error.h"

namespace bouncecal::apps {

void DropCliOptions::Add(CLI::App& command, bool with_law, Geometry geometry) {
  geometry_ = geometry;
  const bool paper = geometry == Geometry::kPaperDefaults;
  auto* preset = command.add_option(
      "--ball", ball_preset,
      "Named ball: " + calibrate::BallPresetNames() +
          " (size and mass from the rules or densities in docs/calibration.md)" +
          (paper ? std::string(" (default: 1 cm steel)")
                 : std::string("; needed with --card, --drag and the Hertz laws")));
  auto* diameter = command.add_option("--diameter", diameter_m,
                                      paper ? "Ball diameter in m (default 0.01)"
                                            : "Ball diameter in m (with --density or --mass)");
  auto* density = command.add_option(
      "--density", density_kg_per_m3,
      paper ? "Ball density in kg/m^3 (default 7800, steel)" : "Ball density in kg/m^3");
  auto* mass = command.add_option("--mass", mass_kg, "Ball mass in kg (instead of --density)");
  density->excludes(mass);
  mass->excludes(density);
  for (auto* explicit_option : {diameter, density, mass}) {
    preset->excludes(explicit_option);
    explicit_option->excludes(preset);
  }
  if (with_law) {
    command.add_option("--law", law,
                       "Contact law: " + dem::ContactLawNames() + " (default walton-braun)");
  }
  command.add_option("--stiffness", stiffness_n_per_m,
                     "Normal stiffness k_n in N/m of the linear laws (default 1e7)");
  command.add_option("--param", parameters,
                     "Fixed law parameter NAME=VALUE in the SI unit of its name, repeatable "
                     "(e.g. --param effective_modulus_pa=1e11)");
  command.add_option(
      "--drop-height", drop_height_m,
      paper ? "Release height of the ball's lowest point above the plate in m (default 0.2)"
            : "Release height of the ball's lowest point above the plate in m. Without it e_1 "
              "and eta_1 are not computed and the simulated drops start from the apex of the "
              "first measured bounce");
  command.add_option("--gravity", gravity_mps2,
                     "Gravitational acceleration in m/s^2 (default 9.81)");
  command.add_option("--integrator", integrator,
                     "Drop integrator: " + dem::IntegratorNames() +
                         " (exact: event-driven, piecewise-linear laws, no drag)");
  command.add_option("--time-step", time_step_s,
                     "Absolute DEM time step in s (default: from --steps-per-contact)");
  command.add_option("--steps-per-contact", steps_per_contact,
                     "Time steps per contact duration (default: the drop engine's accuracy)");
  command.add_flag("--fixed-step-grid", fixed_step_grid,
                   "One fixed step grid from the release, contact switched on at the first step "
                   "with overlap (a classic DEM code, as in the paper)");
  command.add_flag("--drag", drag, "Switch on quadratic air drag (ping-pong and tennis balls)");
  command.add_option("--drag-coefficient", drag_coefficient, "Drag coefficient C_d (default 0.47)");
  command.add_option("--air-density", air_density_kg_per_m3,
                     "Air density in kg/m^3 (default 1.204)");
}

std::optional<dem::Ball> DropCliOptions::GivenBall() const {
  if (!ball_preset.empty()) return calibrate::FindBallPreset(ball_preset).ToBall();
  if (!diameter_m && !density_kg_per_m3 && !mass_kg) return std::nullopt;
  if (geometry_ == Geometry::kAsGiven) {
    if (!diameter_m) {
      throw ConfigError(
          "--density or --mass needs --diameter (the ball's size), or use --ball NAME");
    }
    if (!density_kg_per_m3 && !mass_kg) {
      throw ConfigError(
          "--diameter needs --density or --mass (the ball's mass), or use --ball NAME");
    }
  }
  dem::Ball ball;  // completed with the paper's 1 cm steel under kPaperDefaults
  if (diameter_m) ball.diameter_m = *diameter_m;
  if (density_kg_per_m3) ball.density_kg_per_m3 = *density_kg_per_m3;
  ball.mass_kg = mass_kg;
  if (!(ball.diameter_m > 0 && ball.diameter_m < 10)) {
    throw ConfigError("--diameter must be in (0, 10) m, got " + std::to_string(ball.diameter_m));
  }
  if (!(ball.density_kg_per_m3 > 0 && ball.density_kg_per_m3 < 1e5)) {
    throw ConfigError("--density must be in (0, 1e5) kg/m^3, got " +
                      std::to_string(ball.density_kg_per_m3));
  }
  if (mass_kg && !(*mass_kg > 0 && std::isfinite(*mass_kg))) {
    throw ConfigError("--mass must be a positive number of kg, got " + std::to_string(*mass_kg));
  }
  return ball;
}

dem::Ball DropCliOptions::Ball() const { return GivenBall().value_or(dem::Ball{}); }

dem::ContactLawConfig DropCliOptions::Law(bool validate) const {
  dem::ContactLawConfig config;
  config.kind = dem::ContactLawKindFromString(law);
  if (stiffness_n_per_m) config.parameters["stiffness_n_per_m"] = *stiffness_n_per_m;
  for (const auto& assignment : parameters) {
    const auto equals = assignment.find('=');
    double value = 0;
    bool parsed = false;
    if (equals != std::string::npos) {
      try {
        size_t used = 0;
        value = std::stod(assignment.substr(equals + 1), &used);
        parsed = used == assignment.size() - equals - 1;
      } catch (const std::exception&) {
      }
    }
    if (!parsed) {
      throw ConfigError("--param '" + assignment + "' must be NAME=VALUE with a number, e.g. " +
                        "gamma_n=0.4");
    }
    config.parameters[assignment.substr(0, equals)] = value;
  }
  if (validate) config.Validate();
  return config;
}

dem::Integrator DropCliOptions::Integrator() const { return dem::IntegratorFromString(integrator); }

dem::AirDrag DropCliOptions::Drag() const {
  dem::AirDrag air;
  air.enabled = drag;
  air.drag_coefficient = drag_coefficient;
  air.air_density_kg_per_m3 = air_density_kg_per_m3;
  return air;
}

dem::DropOptions DropCliOptions::DropSetUp() const {
  dem::DropOptions drop;
  drop.law = Law();
  drop.ball = Ball();
  drop.drop_height_m = DropHeightM();
  drop.gravity_mps2 = gravity_mps2;
  drop.drag = Drag();
  drop.integrator = Integrator();
  drop.time_step_s = time_step_s;
  if (steps_per_contact) drop.steps_per_contact = *steps_per_contact;
  drop.fixed_step_grid = fixed_step_grid;
  return drop;
}

}  // namespace bouncecal::apps
