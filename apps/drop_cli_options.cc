#include "drop_cli_options.h"

#include <fmt/core.h>

#include <cmath>
#include <string>
#include <string_view>

#include "bouncecal/calibrate/ball_choice.h"
#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/calibrate/contact_stiffness.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "option_alias.h"

namespace bouncecal::apps {
namespace {

// The law parameter a shortcut option (--gamma, --stiffness-n-per-m, --modulus-pa) sets: the one
// whose ParameterSpec::alias the option names; a law without one refuses the option.
void SetLawParameter(dem::ContactLawConfig& config, std::string_view option, double value) {
  for (const dem::ParameterSpec& spec : dem::ParameterSpecs(config.kind)) {
    if (!spec.alias.empty() && option.substr(2) == spec.alias) {
      config.parameters[std::string(spec.name)] = value;
      return;
    }
  }
  throw ConfigError(
      fmt::format("{} does not apply to the {} law; set its parameters with --param NAME=VALUE",
                  option, dem::ToString(config.kind)));
}

// "gamma_n of walton-braun, damping_ratio of linear-dashpot": what an alias sets, for its help.
std::string AliasTargets(std::string_view alias) {
  std::string targets;
  for (dem::ContactLawKind kind : dem::kAllContactLawKinds) {
    for (const dem::ParameterSpec& spec : dem::ParameterSpecs(kind)) {
      if (spec.alias != alias) continue;
      targets +=
          fmt::format("{}{} of {}", targets.empty() ? "" : ", ", spec.name, dem::ToString(kind));
    }
  }
  return targets;
}

}  // namespace

void DropCliOptions::Add(CLI::App& command, Features features, Geometry geometry) {
  geometry_ = geometry;
  const bool paper = geometry == Geometry::kPaperDefaults;
  auto* preset = command.add_option(
      "--ball", ball_preset,
      "Named ball: " + calibrate::BallPresetNames() +
          " (size and mass from the rules or densities in docs/calibration.md)" +
          (paper ? std::string(" (default: 1 cm steel)")
                 : std::string("; needed with --card, --drag and the Hertz laws")));
  auto* diameter =
      command.add_option("--diameter-m", diameter_m,
                         paper ? "Ball diameter in m (default 0.01)"
                               : "Ball diameter in m (with --density-kg-per-m3 or --mass-kg)");
  auto* density = command.add_option(
      "--density-kg-per-m3", density_kg_per_m3,
      paper ? "Ball density in kg/m^3 (default 7800, steel)" : "Ball density in kg/m^3");
  auto* mass =
      command.add_option("--mass-kg", mass_kg, "Ball mass in kg (instead of --density-kg-per-m3)");
  density->excludes(mass);
  std::vector<CLI::Option*> ball_options = {preset, diameter, density, mass};
  for (auto* explicit_option : {diameter, density, mass}) preset->excludes(explicit_option);
  AddDeprecatedAlias(command, diameter, "--diameter", diameter_m);
  AddDeprecatedAlias(command, density, "--density", density_kg_per_m3);
  AddDeprecatedAlias(command, mass, "--mass", mass_kg);

  CLI::Option* law_option = nullptr;
  if (features.law) {
    law_option = command.add_option(
        "--law", law, "Contact law: " + dem::ContactLawNames() + " (default walton-braun)");
  }
  if (features.material) {
    auto* card = command.add_option(
        "--material", material,
        "Material card (JSON, bouncecal calibrate --card): its law and ball, its fit's drop "
        "height unless --drop-height-m is given and its air drag unless --drag or --no-drag is; "
        "--param and the law shortcuts change single parameters of it");
    if (law_option) card->excludes(law_option);
    for (auto* ball_option : ball_options) card->excludes(ball_option);
  }
  if (features.gamma) {
    command.add_option("--gamma", gamma, "Damping (dimensionless): " + AliasTargets("gamma"));
  }
  auto* stiffness =
      command.add_option("--stiffness-n-per-m", stiffness_n_per_m,
                         "Normal (loading) stiffness k_n in N/m of the linear laws (default 1e7)");
  AddDeprecatedAlias(command, stiffness, "--stiffness", stiffness_n_per_m);
  auto* modulus = command.add_option(
      "--modulus-pa", modulus_pa, "Effective modulus E* in Pa of the Hertz laws (default 1.1e11)");
  AddDeprecatedAlias(command, modulus, "--modulus", modulus_pa);
  auto* contact = command.add_option(
      "--contact-duration-s", contact_duration_s,
      "Contact duration in s of the ball on the plate (measured, or e.g. 0.005 for a tennis "
      "ball): sets k_n (or E*) so the law's closed-form contact lasts that long for this ball at "
      "the release speed sqrt(2 g h0) (docs/physics.md)");
  contact->excludes(stiffness);
  contact->excludes(modulus);
  command.add_option("--param", parameters,
                     "Fixed law parameter NAME=VALUE in the SI unit of its name, repeatable "
                     "(e.g. --param unloading_stiffness_n_per_m=3e7)");
  if (paper) {
    auto* height = command.add_option(
        "--drop-height-m", drop_height_m,
        "Release height of the ball's lowest point above the plate in m (default 0.2)");
    AddDeprecatedAlias(command, height, "--drop-height", drop_height_m);
  } else {
    auto* height = command.add_option(
        "--drop-height-m", drop_heights_m,
        "Release height of the ball's lowest point above the plate in m: once for every "
        "recording (and every drop in it), or once per recording in order. Checked against the "
        "later bounces. Without it e_1 and eta_1 are not computed and the simulated drops start "
        "from the apex of the first measured bounce");
    height->allow_extra_args(false);
    AddDeprecatedAlias(command, height, "--drop-height", drop_heights_m)->allow_extra_args(false);
  }
  auto* gravity = command.add_option("--gravity-mps2", gravity_mps2,
                                     "Gravitational acceleration in m/s^2 (default 9.81)");
  AddDeprecatedAlias(command, gravity, "--gravity", gravity_mps2);
  command.add_option("--integrator", integrator,
                     "Drop integrator: " + dem::IntegratorNames() +
                         " (exact: event-driven, piecewise-linear laws, no drag)");
  auto* step = command.add_option(
      "--time-step-s", time_step_s,
      "Absolute DEM time step in s (default: the contact duration / --steps-per-contact)");
  AddDeprecatedAlias(command, step, "--time-step", time_step_s);
  AddDeprecatedAlias(command, step, "--dt", time_step_s);
  command.add_option("--steps-per-contact", steps_per_contact,
                     "Time steps per contact duration (count; default: the drop engine's 50)");
  command.add_flag("--fixed-step-grid", fixed_step_grid,
                   "One fixed step grid from the release, contact switched on at the first step "
                   "with overlap (a classic DEM code, as in the paper)");
  auto* drag_on = command.add_flag(
      "--drag", drag,
      features.material
          ? "Switch on quadratic air drag (ping-pong and tennis balls); default: the card's "
            "setting with --material, else off"
          : "Switch on quadratic air drag (ping-pong and tennis balls)");
  if (features.material) {
    command.add_flag("--no-drag", no_drag, "Switch air drag off whatever the --material card says")
        ->excludes(drag_on);
  }
  command.add_option("--drag-coefficient", drag_coefficient,
                     "Drag coefficient C_d (dimensionless, default 0.47)");
  auto* air = command.add_option("--air-density-kg-per-m3", air_density_kg_per_m3,
                                 "Air density in kg/m^3 (default 1.204)");
  AddDeprecatedAlias(command, air, "--air-density", air_density_kg_per_m3);
}

void DropCliOptions::ReadMaterial() {
  if (material.empty()) return;
  // CLI11 refuses the canonical spellings together with --material; the old ones land here.
  if (!ball_preset.empty() || diameter_m || density_kg_per_m3 || mass_kg) {
    throw ConfigError("--material takes the ball from the card; leave out the ball options");
  }
  card_ = calibrate::ReadMaterialCard(material);
}

std::optional<dem::Ball> DropCliOptions::GivenBall() const {
  if (card_) return card_->ball;
  // The rules are Python's too (calibrate::ResolveBall); its OptionErrors name the fields, which
  // main() spells as these flags.
  calibrate::BallChoice choice;
  if (!ball_preset.empty()) choice.preset = ball_preset;
  choice.diameter_m = diameter_m;
  choice.density_kg_per_m3 = density_kg_per_m3;
  choice.mass_kg = mass_kg;
  return calibrate::ResolveBall(choice, geometry_ == Geometry::kAsGiven
                                            ? calibrate::BallCompletion::kAsGiven
                                            : calibrate::BallCompletion::kPaperBall);
}

dem::Ball DropCliOptions::Ball() const { return GivenBall().value_or(dem::Ball{}); }

double DropCliOptions::DropHeightM() const {
  if (drop_height_m) return *drop_height_m;
  if (card_ && card_->fit.drop_height_m) return *card_->fit.drop_height_m;
  return 0.2;
}

dem::ContactLawKind DropCliOptions::LawKind() const {
  if (card_) return card_->law.kind;
  return dem::ContactLawKindFromString(law.value_or("walton-braun"));
}

dem::ContactLawConfig DropCliOptions::Law(bool validate) const {
  dem::ContactLawConfig config;
  if (card_) {
    config = card_->law;
  } else {
    config.kind = LawKind();
  }
  if (gamma) SetLawParameter(config, "--gamma", *gamma);
  if (stiffness_n_per_m) SetLawParameter(config, "--stiffness-n-per-m", *stiffness_n_per_m);
  if (modulus_pa) SetLawParameter(config, "--modulus-pa", *modulus_pa);
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
  if (contact_duration_s) {
    const std::string elastic(calibrate::ElasticParameterName(config.kind));
    for (const auto& assignment : parameters) {
      if (assignment.rfind(elastic + "=", 0) == 0) {
        throw ConfigError("--contact-duration-s and --param " + elastic +
                          " both set the stiffness; give one of them");
      }
    }
    if (geometry_ == Geometry::kAsGiven && !GivenBall()) {
      throw ConfigError(
          "--contact-duration-s needs the ball (its mass sets the stiffness that gives that "
          "duration); give --ball NAME or --diameter-m with --mass-kg");
    }
    config = calibrate::WithContactDuration(
        config, Ball(), std::sqrt(2 * gravity_mps2 * DropHeightM()), *contact_duration_s);
  }
  if (validate) config.Validate();
  return config;
}

dem::Integrator DropCliOptions::Integrator() const { return dem::IntegratorFromString(integrator); }

std::string_view DropCliOptions::DropHeightSource() const {
  if (drop_height_m) return "command line";
  if (card_ && card_->fit.drop_height_m) return "card";
  return "default";
}

std::string_view DropCliOptions::DragSource() const {
  if (drag || no_drag) return "command line";
  if (card_) return "card";
  return "default";
}

dem::AirDrag DropCliOptions::Drag() const {
  dem::AirDrag air;
  // The card's drops were fitted with or without drag; simulating them otherwise moves the
  // heights of a light ball by far more than its damping does (compare: 0.164 m RMS against
  // 0.047 m on a tennis-like recording).
  air.enabled = drag || (!no_drag && card_ && card_->fit.drag);
  air.drag_coefficient = drag_coefficient;
  air.air_density_kg_per_m3 = air_density_kg_per_m3;
  return air;
}

dem::DropOptions DropCliOptions::DropSetUp(bool validate_law) const {
  dem::DropOptions drop;
  drop.law = Law(validate_law);
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
