// bouncecal.export and bouncecal.export_check: the LAMMPS / LIGGGHTS decks of a material card
// (export/, bouncecal/export/*.h) and the check of an engine's run of the single-drop deck.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "bindings.h"
#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "bouncecal/export/drop_deck.h"
#include "bouncecal/export/drop_deck_check.h"
#include "bouncecal/export/packing_deck.h"
#include "bouncecal/export/scene_packing.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

calibrate::ExportMaterial MaterialFromPython(py::handle material) {
  if (IsPathLike(material)) return calibrate::ReadExportMaterial(ToPath(material, "material"));
  if (py::isinstance<py::dict>(material)) {
    return calibrate::ExportMaterialFromJson(ToJson(material, "material"), "material");
  }
  throw ConfigError(
      "material must be a material card's path or its dict (Calibration.card()), got a " +
      py::type::of(material).attr("__name__").cast<std::string>());
}

py::object DeckToPython(const calibrate::Deck& deck, const std::vector<std::string>& extra_notes) {
  py::object result = NewResult();
  py::object files = NewResult();
  for (const auto& file : deck.files) files[py::str(file.name)] = file.content;
  result["files"] = files;
  result["input_file_name"] = deck.input_file_name;
  result["run_command"] = deck.run_command;
  result["trajectory_file_name"] = deck.trajectory_file_name;
  result["time_step_s"] = deck.time_step_s;
  result["steps"] = deck.steps;
  result["duration_s"] = deck.duration_s;
  result["output_every_steps"] = deck.output_every_steps;
  result["output_interval_s"] = deck.output_interval_s;
  result["expected_restitution"] = deck.expected_restitution;
  result["time_step_error_bound"] = deck.time_step_error_bound;
  std::vector<std::string> notes = deck.notes;
  notes.insert(notes.end(), extra_notes.begin(), extra_notes.end());
  result["notes"] = StringList(notes);
  return result;
}

void WriteDeck(const std::filesystem::path& folder, const calibrate::Deck& deck) {
  for (const auto& file : deck.files) WriteFileAtomically(folder / file.name, file.content);
}

py::object CheckToPython(const calibrate::DropDeckCheck& check) {
  std::vector<double> start, end, speed_in, speed_out, restitution, e_dev, t_dev, gravity, allowed;
  std::vector<bool> judged, within;
  for (const auto& b : check.bounces) {
    start.push_back(b.bounce.contact_start_s);
    end.push_back(b.bounce.contact_end_s);
    speed_in.push_back(b.bounce.impact_speed_mps);
    speed_out.push_back(b.bounce.rebound_speed_mps);
    restitution.push_back(b.bounce.restitution);
    e_dev.push_back(b.restitution_deviation);
    t_dev.push_back(b.duration_deviation);
    gravity.push_back(b.gravity_effect);
    allowed.push_back(b.allowed_deviation);
    judged.push_back(b.judged);
    within.push_back(b.within);
  }
  auto bools = [](const std::vector<bool>& values) {
    py::array_t<bool> array(static_cast<py::ssize_t>(values.size()));
    auto view = array.mutable_unchecked<1>();
    for (std::size_t i = 0; i < values.size(); ++i) view(static_cast<py::ssize_t>(i)) = values[i];
    return array;
  };
  py::object bounces = NewResult("Table");
  bounces["contact_start_s"] = FloatArray(start);
  bounces["contact_end_s"] = FloatArray(end);
  bounces["impact_speed_mps"] = FloatArray(speed_in);
  bounces["rebound_speed_mps"] = FloatArray(speed_out);
  bounces["restitution"] = FloatArray(restitution);
  bounces["restitution_deviation"] = FloatArray(e_dev);
  bounces["duration_deviation"] = FloatArray(t_dev);
  bounces["gravity_effect"] = FloatArray(gravity);
  bounces["allowed_deviation"] = FloatArray(allowed);
  bounces["judged"] = bools(judged);
  bounces["within"] = bools(within);
  py::object result = NewResult();
  result["passed"] = check.passed;
  result["judged"] = check.judged;
  result["within"] = check.within;
  result["unresolved_contacts"] = check.unresolved_contacts;
  result["bounces"] = bounces;
  return result;
}

}  // namespace

void BindExport(py::module_& module) {
  const calibrate::DropDeckOptions drop_defaults;
  const calibrate::PackingDeckOptions packing_defaults;
  module.def(
      "export",
      [](py::object material_argument, const std::string& engine,
         std::optional<std::filesystem::path> output_dir, std::optional<double> drop_height_m,
         double gravity_mps2, std::optional<double> time_step_s, double max_step_error, int bounces,
         py::object scene_argument, int processes) {
        calibrate::DropDeckOptions options;
        options.engine = calibrate::EngineFromString(engine);
        options.gravity_mps2 = gravity_mps2;
        options.time_step_s = time_step_s;
        options.max_time_step_error = max_step_error;
        options.bounces = bounces;
        const auto material = MaterialFromPython(material_argument);
        // The card's own drop height unless one is given, as `bouncecal export`.
        if (drop_height_m) {
          options.drop_height_m = *drop_height_m;
        } else if (material.drop_height_m) {
          options.drop_height_m = *material.drop_height_m;
        }
        const calibrate::Deck deck = calibrate::ExportDropDeck(material, options);
        std::optional<calibrate::Deck> packing;
        std::vector<std::string> packing_notes;
        if (!scene_argument.is_none()) {
          const auto scene_path = ToPath(scene_argument, "scene");
          const dem::Scene scene = dem::LoadScene(scene_path);
          calibrate::PackingDeckOptions packing_options;
          packing_options.engine = options.engine;
          packing_options.processes = processes;
          packing_options.scene_source = scene_path.string();
          packing = calibrate::MakePackingDeck(material, calibrate::PackingDeckSpecFromScene(scene),
                                               packing_options);
          if (dem::ToJson(scene.material.law) != dem::ToJson(material.law)) {
            packing_notes.push_back(
                "the scene names the law " + dem::ToJson(scene.material.law).dump() +
                " but the deck uses the card's " + dem::ToJson(material.law).dump() +
                ": exporting a card means exporting its law");
          }
        }
        // Everything is generated, and so validated, before the first file is written.
        if (output_dir) {
          std::error_code error;
          std::filesystem::create_directories(*output_dir, error);
          if (error || !std::filesystem::is_directory(*output_dir)) {
            throw OutputError("output_dir " + output_dir->string() +
                              ": cannot create the deck folder (" +
                              (error ? error.message() : std::string("not a folder")) +
                              "); choose a writable folder");
          }
          WriteDeck(*output_dir, deck);
          if (packing) WriteDeck(*output_dir, *packing);
        }
        py::object result = DeckToPython(deck, {});
        result["engine"] = std::string(calibrate::ToString(options.engine));
        result["material_source"] = material.source;
        result["drop_height_m"] = options.drop_height_m;
        result["packing"] = packing ? DeckToPython(*packing, packing_notes) : py::none();
        result["output_dir"] =
            output_dir ? py::object(py::str(output_dir->string())) : py::object(py::none());
        return result;
      },
      py::arg("material"), py::arg("engine") = "lammps", py::arg("output_dir") = py::none(),
      py::kw_only(), py::arg("drop_height_m") = py::none(),
      py::arg("gravity_mps2") = drop_defaults.gravity_mps2, py::arg("time_step_s") = py::none(),
      py::arg("max_step_error") = drop_defaults.max_time_step_error,
      py::arg("bounces") = drop_defaults.bounces, py::arg("scene") = py::none(),
      py::arg("processes") = packing_defaults.processes,
      R"doc(Write the LAMMPS or LIGGGHTS decks of a material card, as `bouncecal export`: the
single-drop check deck (in.drop, deck.json) and, with scene, the packing deck of that scene with
the card's law (in.pack).

material: a material card's path or its dict (Calibration.card()).
engine: lammps or liggghts. output_dir: folder the files are written to (created; each file
    replaced atomically); None writes nothing and only returns the files' text.
drop_height_m: release height of the check drop (default: the card's fit height, else 0.2).
max_step_error: bound on the relative restitution error from the time step.

Returns a Result: files ({name: text}), input_file_name, run_command, expected_restitution,
time_step_error_bound, time_step_s, steps, notes (the mapping and what differs), engine,
drop_height_m, packing (the same fields for in.pack, or None) and output_dir.)doc");

  module.def(
      "export_check",
      [](const std::filesystem::path& folder, double max_gravity_effect) {
        calibrate::DropDeckCheckOptions options;
        options.max_gravity_effect = max_gravity_effect;
        return CheckToPython(calibrate::CheckDropDeckFolder(folder, options));
      },
      py::arg("folder"), py::kw_only(),
      py::arg("max_gravity_effect") = calibrate::DropDeckCheckOptions{}.max_gravity_effect,
      R"doc(After the engine ran an exported single-drop deck: compare each bounce's
restitution and contact duration in its trajectory with what the deck promised (deck.json), as
`bouncecal export-check`. Returns a Result: passed, judged, within, unresolved_contacts and
bounces (a Table). Unlike the command, a failed check is not an exception: read `passed`.)doc");
}

}  // namespace bouncecal::python
