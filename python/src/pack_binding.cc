// bouncecal.pack: dem::RunPacking on a scene file or dict, returning the fields of the summary
// `bouncecal pack` writes (dem/packing_json.h), plus the history, profile and final state it
// writes as CSV.
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
#include "bouncecal/dem/packing_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "keywords.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

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

// The summary `bouncecal pack` writes (dem::ToJson) as Python, for a run that did not become
// unstable (those are errors here, as there), then what the command writes as CSV.
py::object ToPython(const dem::Scene& scene, const dem::PackSummary& s) {
  py::object j = FromJson(dem::ToJson(scene, s));
  j["coordination_histogram"] = IntArray(s.coordination.histogram);
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
         double skin_diameters, double min_skin_diameters, bool allow_unstable_step,
         const std::string& precision) {
        if (precision != "double" && precision != "single") {
          throw ConfigError("precision must be \"double\" or \"single\", got \"" + precision +
                            "\"");
        }
        const dem::Scene scene = SceneFromPython(scene_argument);
        dem::PackOptions options;
        options.single_precision_contacts = precision == "single";
        options.threads = threads;
        options.skin_diameters = skin_diameters;
        options.min_skin_diameters = min_skin_diameters;
        options.allow_unstable_step = allow_unstable_step;
        dem::CheckDurationOverride(scene, duration_s);
        options.duration_s = duration_s;
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
          const std::string text = WithKeywords(scene.source.string() + ": " + summary.message);
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
      py::arg("precision") = "double",
      R"doc(Run a packing scene (dem::RunPacking) and measure it: the fields of the summary
`bouncecal pack` writes, plus history (a Table: time_s, packing_density, kinetic_energy_j,
max_speed_mps, particles), profile (a Table: height_m, density) and final_state (position_m and
velocity_mps as (n, dimension) arrays, radius_m, species).

scene: a scene file's path or a scene dict (docs/scenes.md); relative paths inside a dict
    resolve against the working folder. Writes no files (no outputs folder, no dumps).
threads: the engine's worker threads (results are identical for any count). duration_s: the
    simulated time, overriding the scene's (0 measures the start state). precision: "double"
    (the default, bit for bit reproducible) or "single" (the particle pairs' contact arithmetic
    in float, `pack --precision single`; docs/packing.md, "Single precision").
Raises InputError for a bad scene, ConfigError when the run becomes unstable (with the
command line's message) or an option is out of range. A run that ends boiling (the command's
exit status 3) returns its result with boiling true and a RuntimeWarning saying why.)doc");
}

}  // namespace bouncecal::python
