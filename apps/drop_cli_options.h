#ifndef BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
#define BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::apps {

// The ball, the law and the drop set-up shared by calibrate, sweep and compare. Sweep and compare
// simulate the paper's set-up unless told otherwise (1 cm steel, 7800 kg/m^3, h0 = 0.2 m);
// calibrate describes an experiment and assumes none of it (Geometry::kAsGiven).
struct DropCliOptions {
  enum class Geometry {
    kPaperDefaults,  // absent ball and height are the paper's
    kAsGiven,        // absent means not given; a ball must be complete (size and mass)
  };
  std::string ball_preset;  // --ball NAME
  std::optional<double> diameter_m;
  std::optional<double> density_kg_per_m3;
  std::optional<double> mass_kg;
  std::string law = "walton-braun";
  std::optional<double> stiffness_n_per_m;  // unset: the law's default (1e7 N/m)
  std::vector<std::string> parameters;      // NAME=VALUE
  std::optional<double> drop_height_m;
  double gravity_mps2 = 9.81;
  std::string integrator = "verlet";
  std::optional<double> time_step_s;
  std::optional<double> steps_per_contact;
  bool fixed_step_grid = false;
  bool drag = false;
  double drag_coefficient = 0.47;
  double air_density_kg_per_m3 = 1.204;

  // Registers the options on `command`; `geometry` decides the help texts and what absence means.
  void Add(CLI::App& command, bool with_law = true, Geometry geometry = Geometry::kPaperDefaults);
  // The ball the command line describes (--ball, or --diameter with --density or --mass), or
  // nothing when no ball option was given. ConfigError for a value out of range or an incomplete
  // ball under kAsGiven (a size without a mass or the reverse).
  std::optional<dem::Ball> GivenBall() const;
  // GivenBall() completed with the paper's ball (kPaperDefaults: sweep, compare).
  dem::Ball Ball() const;
  double DropHeightM() const { return drop_height_m.value_or(0.2); }  // kPaperDefaults
  // The law with --stiffness and --param applied and validated (ConfigError otherwise). Unvalidated
  // for --compare-laws, where each law takes the --param values it has.
  dem::ContactLawConfig Law(bool validate = true) const;
  dem::Integrator Integrator() const;
  dem::AirDrag Drag() const;
  // The drop set-up every option above describes, in one place so no subcommand can leave one
  // out (sweep once ignored --drag): ball (Ball()), DropHeightM(), gravity, drag, integrator,
  // time step or steps per contact, step grid, and the validated Law().
  dem::DropOptions DropSetUp() const;

 private:
  Geometry geometry_ = Geometry::kPaperDefaults;
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
