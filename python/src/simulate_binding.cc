// bouncecal.simulate_drop: dem::SimulateDrop, returning what `bouncecal simulate drop --json`
// writes plus the trajectory its --trajectory CSV holds.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "arguments.h"
#include "bindings.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/drop.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

py::object ImpactsTable(const dem::DropResult& result) {
  std::vector<double> time, restitution, energy_loss, duration, overlap, speed_in, speed_out;
  std::vector<bool> released;
  for (const dem::DropImpact& impact : result.impacts) {
    time.push_back(impact.time_s);
    restitution.push_back(impact.restitution);
    energy_loss.push_back(impact.energy_loss);
    duration.push_back(impact.contact_duration_s);
    overlap.push_back(impact.max_overlap_m);
    speed_in.push_back(impact.speed_in_mps);
    speed_out.push_back(impact.speed_out_mps);
    released.push_back(impact.released);
  }
  py::array_t<bool> released_array(static_cast<py::ssize_t>(released.size()));
  auto view = released_array.mutable_unchecked<1>();
  for (std::size_t i = 0; i < released.size(); ++i) {
    view(static_cast<py::ssize_t>(i)) = released[i];
  }
  py::object table = NewResult("Table");
  table["time_s"] = FloatArray(time);
  table["restitution"] = FloatArray(restitution);
  table["energy_loss"] = FloatArray(energy_loss);
  table["contact_duration_s"] = FloatArray(duration);
  table["max_overlap_m"] = FloatArray(overlap);
  table["speed_in_mps"] = FloatArray(speed_in);
  table["speed_out_mps"] = FloatArray(speed_out);
  table["released"] = released_array;
  return table;
}

py::object TrajectoryTable(const dem::DropResult& result) {
  std::vector<double> time, height, velocity;
  for (const dem::TrajectoryPoint& point : result.trajectory) {
    time.push_back(point.time_s);
    height.push_back(point.height_m);
    velocity.push_back(point.velocity_mps);
  }
  py::object table = NewResult("Table");
  table["time_s"] = FloatArray(time);
  table["height_m"] = FloatArray(height);
  table["velocity_mps"] = FloatArray(velocity);
  return table;
}

// The fields of `bouncecal simulate drop --json` (apps/simulate_command.cc), then the trajectory.
py::object ToPython(const dem::DropResult& result, const dem::DropOptions& options) {
  py::object out = NewResult();
  out["format"] = "bouncecal-drop/1";  // docs/json.md
  out["impacts"] = ImpactsTable(result);
  out["stop_reason"] = std::string(dem::ToString(result.stop_reason));
  out["stop_detail"] = result.stop_detail;
  out["steps"] = result.steps;
  out["time_step_s"] = result.time_step_s;
  out["stability_limit_s"] = result.stability_limit_s;
  out["integrator"] = std::string(dem::ToString(options.integrator));
  out["contact_law"] = FromJson(dem::ToJson(options.law));
  py::object ball = NewResult();
  ball["diameter_m"] = options.ball.diameter_m;
  ball["density_kg_per_m3"] = options.ball.DensityKgPerM3();
  ball["mass_kg"] = options.ball.MassKg();
  out["ball"] = ball;
  out["drop_height_m"] = options.drop_height_m;
  out["gravity_mps2"] = options.gravity_mps2;
  out["trajectory"] = TrajectoryTable(result);
  return out;
}

}  // namespace

void BindSimulate(py::module_& module) {
  const dem::DropOptions defaults;
  module.def(
      "simulate_drop",
      [](py::object law, py::object parameters, std::optional<std::string> ball,
         std::optional<double> diameter_m, std::optional<double> density_kg_per_m3,
         std::optional<double> mass_kg, double drop_height_m, double gravity_mps2,
         const std::string& integrator, std::optional<double> time_step_s, double steps_per_contact,
         bool allow_unstable_step, bool fixed_step_grid, bool locate_contact_events, bool drag,
         double drag_coefficient, double air_density_kg_per_m3, int max_impacts, double max_time_s,
         double rest_flight_s, double rest_contact_factor, double trajectory_interval_s) {
        dem::DropOptions options;
        options.law = LawFromPython(law, parameters);
        options.ball =
            BallFromArguments({ball, diameter_m, density_kg_per_m3, mass_kg}, /*complete=*/false)
                .value_or(dem::Ball{});
        options.drop_height_m = drop_height_m;
        options.gravity_mps2 = gravity_mps2;
        options.integrator = dem::IntegratorFromString(integrator);
        options.time_step_s = time_step_s;
        options.steps_per_contact = steps_per_contact;
        options.allow_unstable_step = allow_unstable_step;
        options.fixed_step_grid = fixed_step_grid;
        options.locate_contact_events = locate_contact_events;
        options.drag = {.enabled = drag,
                        .drag_coefficient = drag_coefficient,
                        .air_density_kg_per_m3 = air_density_kg_per_m3};
        options.max_impacts = max_impacts;
        options.max_time_s = max_time_s;
        options.rest_flight_s = rest_flight_s;
        options.rest_contact_factor = rest_contact_factor;
        options.trajectory_interval_s = trajectory_interval_s;
        dem::DropResult result;
        {
          py::gil_scoped_release release;
          result = dem::SimulateDrop(options);
        }
        return ToPython(result, options);
      },
      py::arg("law") = "walton-braun", py::arg("parameters") = py::none(), py::kw_only(),
      py::arg("ball") = py::none(), py::arg("diameter_m") = py::none(),
      py::arg("density_kg_per_m3") = py::none(), py::arg("mass_kg") = py::none(),
      py::arg("drop_height_m") = defaults.drop_height_m,
      py::arg("gravity_mps2") = defaults.gravity_mps2,
      py::arg("integrator") = std::string(dem::ToString(defaults.integrator)),
      py::arg("time_step_s") = py::none(),
      py::arg("steps_per_contact") = defaults.steps_per_contact,
      py::arg("allow_unstable_step") = defaults.allow_unstable_step,
      py::arg("fixed_step_grid") = defaults.fixed_step_grid,
      py::arg("locate_contact_events") = defaults.locate_contact_events,
      py::arg("drag") = defaults.drag.enabled,
      py::arg("drag_coefficient") = defaults.drag.drag_coefficient,
      py::arg("air_density_kg_per_m3") = defaults.drag.air_density_kg_per_m3,
      py::arg("max_impacts") = defaults.max_impacts, py::arg("max_time_s") = defaults.max_time_s,
      py::arg("rest_flight_s") = defaults.rest_flight_s,
      py::arg("rest_contact_factor") = defaults.rest_contact_factor,
      py::arg("trajectory_interval_s") = 1e-4,
      R"doc(Drop a sphere on a rigid plane until it rests (dem::SimulateDrop): what
`bouncecal simulate drop --json` writes, plus the trajectory its --trajectory CSV holds.

law: a law name (e.g. walton-braun or hertz; an unknown name's ConfigError lists
    them all) or a {'law': ..., 'parameters': {...}} dict, e.g. a material card's contact_law.
parameters: {name: value} of the law's parameters in SI (e.g. {'gamma_n': 0.4}); the others
    keep their defaults.
ball: a preset name (steel-10mm, ...), or diameter_m with density_kg_per_m3 or mass_kg
    (default: 1 cm steel, 7800 kg/m^3).
integrator: verlet, euler, rk4 or exact. trajectory_interval_s: 0 records no trajectory.
The other keywords are dem::DropOptions' fields (bouncecal/dem/drop.h), same names and defaults.

Returns a Result: impacts (a Table of numpy columns time_s, restitution, energy_loss,
contact_duration_s, max_overlap_m, speed_in_mps, speed_out_mps, released), stop_reason, ...,
trajectory (a Table: time_s, height_m, velocity_mps). Raises ConfigError for parameters out of
range or an unstable time step.)doc");
}

}  // namespace bouncecal::python
