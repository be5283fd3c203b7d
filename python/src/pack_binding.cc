// bouncecal.pack: dem::RunPacking on a scene file or dict, returning the fields of the summary
// `bouncecal pack` writes, plus the history, profile and final state it writes as CSV.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

// The command line leaves a value that is not a number out of its summary rather than writing
// null (apps/pack_command.cc, PutFinite); so does this.
void PutFinite(py::object& result, const char* key, double value) {
  if (std::isfinite(value)) result[key] = value;
}

py::array_t<double> Vectors(const std::vector<dem::Vec3>& vectors, int dimension) {
  py::array_t<double> array(
      {static_cast<py::ssize_t>(vectors.size()), static_cast<py::ssize_t>(dimension)});
  auto view = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < vectors.size(); ++i) {
    for (int c = 0; c < dimension; ++c) {
      view(static_cast<py::ssize_t>(i), c) = vectors[i][static_cast<std::size_t>(c)];
    }
  }
  return array;
}

py::object History(const dem::PackSummary& summary) {
  std::vector<double> time, density, kinetic, speed;
  std::vector<std::int64_t> particles;
  for (const auto& point : summary.history) {
    time.push_back(point.time_s);
    density.push_back(point.packing_density);
    kinetic.push_back(point.kinetic_energy_j);
    speed.push_back(point.max_speed_mps);
    particles.push_back(point.particles);
  }
  py::object table = NewResult("Table");
  table["time_s"] = FloatArray(time);
  table["packing_density"] = FloatArray(density);
  table["kinetic_energy_j"] = FloatArray(kinetic);
  table["max_speed_mps"] = FloatArray(speed);
  table["particles"] = IntArray(particles);
  return table;
}

py::object FinalState(const dem::ParticleSnapshot& state) {
  py::object result = NewResult();
  result["time_s"] = state.time_s;
  result["position_m"] = Vectors(state.position_m, state.dimension);
  result["velocity_mps"] = Vectors(state.velocity_mps, state.dimension);
  result["radius_m"] = FloatArray(state.radius_m);
  result["species"] = IntArray(state.species);
  return result;
}

// The summary of `bouncecal pack` (apps/pack_command.cc, SummaryJson), in its order, for a run
// that did not become unstable (those are errors here, as there).
py::object ToPython(const dem::Scene& scene, const dem::PackSummary& s) {
  py::object j = NewResult();
  j["format"] = "bouncecal-pack/1";  // docs/json.md
  j["scene"] = scene.source.string();
  j["physics"] = s.physics;
  j["stop_reason"] = std::string(dem::ToString(s.stop_reason));
  j["message"] = s.message;
  j["state_digest"] = fmt::format("{:016x}", s.state_digest);
  j["boiling"] = s.boiling;
  PutFinite(j, "packing_density", s.packing_density);
  PutFinite(j, "packing_density_by_count", s.packing_density_by_count);
  PutFinite(j, "mean_coordination", s.coordination.mean);
  j["coordination_histogram"] = IntArray(s.coordination.histogram);
  j["coordination_particles"] = s.coordination.particles;
  j["particles"] = s.particles;
  j["particles_not_inserted"] = s.particles_not_inserted;
  j["steps"] = s.steps;
  PutFinite(j, "time_step_s", s.time_step_s);
  PutFinite(j, "time_step_limit_s", s.time_step_limit_s);
  PutFinite(j, "tangential_time_step_limit_s", s.tangential_time_step_limit_s);
  j["warnings"] = StringList(s.warnings);
  PutFinite(j, "simulated_s", s.simulated_s);
  PutFinite(j, "kinetic_energy_j", s.kinetic_energy_j);
  j["neighbor_rebuilds"] = s.neighbor_rebuilds;
  j["threads"] = s.threads;
  PutFinite(j, "wall_s", s.wall_s);
  PutFinite(j, "total_wall_s", s.total_wall_s);
  PutFinite(j, "particle_steps_per_s", s.particle_steps_per_s);
  if (scene.dimension == 3) {
    j["band_m"] = FloatArray({scene.measurement.band_min_m, scene.measurement.band_max_m});
  } else {
    const auto& lo = scene.measurement.window_min_m;
    const auto& hi = scene.measurement.window_max_m;
    py::array_t<double> window({2, 2});
    auto view = window.mutable_unchecked<2>();
    view(0, 0) = lo[0];
    view(0, 1) = lo[1];
    view(1, 0) = hi[0];
    view(1, 1) = hi[1];
    j["window_m"] = window;
  }
  // Beyond the summary: what the command writes as history.csv, profile.csv and particles.csv.
  j["history"] = History(s);
  py::object profile = NewResult("Table");
  profile["height_m"] = FloatArray(s.profile.height_m);
  profile["density"] = FloatArray(s.profile.density);
  j["profile"] = profile;
  j["final_state"] = FinalState(s.final_state);
  return j;
}

dem::Scene SceneFromPython(py::handle scene) {
  if (IsPathLike(scene)) return dem::LoadScene(ToPath(scene, "scene"));
  if (py::isinstance<py::dict>(scene)) {
    // Relative paths in the dict (a start-positions file, a material card) resolve against the
    // working folder, as those of a scene file resolve against its folder.
    return dem::SceneFromJson(ToJson(scene, "scene"),
                              std::filesystem::current_path() / "(scene dict)");
  }
  throw ConfigError("scene must be a scene file's path or a scene dict (docs/scenes.md), got a " +
                    py::type::of(scene).attr("__name__").cast<std::string>());
}

}  // namespace

void BindPack(py::module_& module) {
  const dem::PackOptions defaults;
  module.def(
      "pack",
      [](py::object scene_argument, int threads, std::optional<double> duration_s,
         double skin_diameters, double min_skin_diameters, bool allow_unstable_step) {
        const dem::Scene scene = SceneFromPython(scene_argument);
        dem::PackOptions options;
        options.threads = threads;
        options.skin_diameters = skin_diameters;
        options.min_skin_diameters = min_skin_diameters;
        options.allow_unstable_step = allow_unstable_step;
        if (duration_s) {
          // As `bouncecal pack --duration`: a positive duration under one step would run none
          // and report the start state as the result; 0 asks for exactly that.
          if (!(*duration_s >= 0 && *duration_s <= 1e6)) {
            throw ConfigError("duration_s must be in [0, 1e6] s, got " +
                              std::to_string(*duration_s));
          }
          if (*duration_s > 0 && *duration_s < scene.time_step_s) {
            throw ConfigError("duration_s " + std::to_string(*duration_s) +
                              " s is below the scene's time_step_s (" +
                              std::to_string(scene.time_step_s) + " s in " + scene.source.string() +
                              "), so no step would run; give at least one step, or 0 to "
                              "measure the start state");
          }
          options.duration_s = *duration_s;
        }
        // Ctrl-C between progress reports stops the run (KeyboardInterrupt) instead of being
        // ignored until it ends.
        options.progress = [](const dem::PackProgress&) {
          py::gil_scoped_acquire acquire;
          if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        };
        dem::PackSummary summary;
        {
          py::gil_scoped_release release;
          summary = dem::RunPacking(scene, options);
        }
        if (summary.stop_reason == dem::PackStopReason::kUnstable) {
          throw ConfigError(scene.source.string() + ": " + summary.message);
        }
        if (summary.boiling) {
          // The command exits 3 and still writes what it measured; here the result is returned
          // with a RuntimeWarning, so a script that never reads result["boiling"] still hears
          // that its "packing" is a boiling state.
          const std::string text = scene.source.string() + ": " + summary.message;
          if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) {
            throw py::error_already_set();  // warnings turned into errors
          }
        }
        return ToPython(scene, summary);
      },
      py::arg("scene"), py::kw_only(), py::arg("threads") = defaults.threads,
      py::arg("duration_s") = py::none(), py::arg("skin_diameters") = defaults.skin_diameters,
      py::arg("min_skin_diameters") = defaults.min_skin_diameters,
      py::arg("allow_unstable_step") = defaults.allow_unstable_step,
      R"doc(Run a packing scene (dem::RunPacking) and measure it: the fields of the summary
`bouncecal pack` writes, plus history (a Table: time_s, packing_density, kinetic_energy_j,
max_speed_mps, particles), profile (a Table: height_m, density) and final_state (position_m and
velocity_mps as (n, dimension) arrays, radius_m, species).

scene: a scene file's path or a scene dict (docs/scenes.md); relative paths inside a dict
    resolve against the working folder. Writes no files (no outputs folder, no dumps).
threads: the engine's worker threads (results are identical for any count). duration_s: the
    simulated time, overriding the scene's (0 measures the start state).
Raises InputError for a bad scene, ConfigError when the run becomes unstable (with the
command line's message) or an option is out of range. A run that ends boiling (the command's
exit status 3) returns its result with boiling true and a RuntimeWarning saying why.)doc");
}

}  // namespace bouncecal::python
