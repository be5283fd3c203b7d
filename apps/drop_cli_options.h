#ifndef BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
#define BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::apps {

// The ball, the law and the drop set-up shared by calibrate, sweep and compare, with the paper's
// defaults (1 cm steel, 7800 kg/m^3, walton-braun, k_n = 1e7 N/m, h0 = 0.2 m).
struct DropCliOptions {
  double diameter_m = 0.01;
  double density_kg_per_m3 = 7800;
  std::optional<double> mass_kg;
  std::string law = "walton-braun";
  std::optional<double> stiffness_n_per_m;  // unset: the law's default (1e7 N/m)
  std::vector<std::string> parameters;      // NAME=VALUE
  double drop_height_m = 0.2;
  double gravity_mps2 = 9.81;
  std::string integrator = "verlet";
  std::optional<double> time_step_s;
  std::optional<double> steps_per_contact;
  bool fixed_step_grid = false;
  bool drag = false;
  double drag_coefficient = 0.47;
  double air_density_kg_per_m3 = 1.204;

  // Registers the options on `command`.
  void Add(CLI::App& command, bool with_law = true);
  dem::Ball Ball() const;
  // The law with --stiffness and --param applied and validated (ConfigError otherwise). Unvalidated
  // for --compare-laws, where each law takes the --param values it has.
  dem::ContactLawConfig Law(bool validate = true) const;
  dem::Integrator Integrator() const;
  dem::AirDrag Drag() const;
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
