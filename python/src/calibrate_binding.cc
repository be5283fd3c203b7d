// bouncecal.calibrate: calibrate::Fit over the sequences of recordings, impact-time files, arrays
// of onsets or analyze() results, returning what `bouncecal calibrate --json` writes, and the
// material card of the fit on request (Calibration.card / write_card in bouncecal/_result.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "arguments.h"
#include "bindings.h"
#include "bouncecal/calibrate/contact_stiffness.h"
#include "bouncecal/calibrate/content_hash.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/fit_json.h"
#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/calibrate/recording_manifest.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

// What a material card of a finished fit is made from.
struct CardSource {
  calibrate::FitSummary summary;
  calibrate::FitOptions options;
  std::vector<std::filesystem::path> recordings;  // the input files, hashed into the card
};

std::time_t CreationTime(std::optional<std::int64_t> created_at) {
  if (!created_at) return CardCreationTime();
  if (*created_at < 0) {
    throw ConfigError("created_at must be seconds since 1970-01-01 UTC (>= 0), got " +
                      std::to_string(*created_at));
  }
  return static_cast<std::time_t>(*created_at);
}

calibrate::MaterialCard MakeCard(const CardSource& source, std::optional<std::int64_t> created_at) {
  if (!source.options.ball_given) {
    throw ConfigError(
        "a material card records the ball its damping was calibrated with (exported damping "
        "scales with its mass); give calibrate() ball=NAME, or diameter_m with "
        "density_kg_per_m3 or mass_kg");
  }
  return calibrate::MakeMaterialCard(source.summary, source.options, source.recordings,
                                     CreationTime(created_at));
}

std::string Describe(std::size_t index) { return "inputs[" + std::to_string(index) + "]"; }

// A 1-D array of onset times in s (each with onset_uncertainty_s), or an (n, 2) array of onsets
// and their one-sigma uncertainties.
calibrate::MeasuredSequence SequenceFromArray(py::handle value, std::size_t index,
                                              double default_uncertainty_s) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  const std::string name = Describe(index);
  if (!array || !(array.ndim() == 1 || (array.ndim() == 2 && array.shape(1) == 2))) {
    throw InputError(name +
                     ": give a path, an analyze() result, a 1-D array of onset times in s or an "
                     "(n, 2) array of onsets and their uncertainties");
  }
  calibrate::MeasuredSequence sequence;
  sequence.source = "array " + std::to_string(index);
  const bool with_sigma = array.ndim() == 2;
  const auto rows = array.shape(0);
  for (py::ssize_t i = 0; i < rows; ++i) {
    const double onset = with_sigma ? array.at(i, 0) : array.at(i);
    const double sigma = with_sigma ? array.at(i, 1) : default_uncertainty_s;
    if (!std::isfinite(onset) || !(sigma > 0 && std::isfinite(sigma))) {
      throw InputError(name + ": row " + std::to_string(i) +
                       " needs a finite onset and a positive, finite uncertainty in s");
    }
    sequence.impacts.push_back({onset, sigma});
  }
  return sequence;
}

// The sequences of an analyze() result, named and hashed as LoadSequences names a recording's.
std::vector<calibrate::MeasuredSequence> SequencesFromAnalysis(
    py::handle analysis, std::size_t index, std::vector<std::filesystem::path>& recordings) {
  const py::dict fields = py::reinterpret_borrow<py::dict>(analysis);
  std::optional<std::filesystem::path> file;
  if (fields.contains("file") && !fields["file"].is_none()) {
    file = ToPath(fields["file"], Describe(index) + "['file']");
    recordings.push_back(*file);
  }
  const std::string hash = file ? calibrate::FileContentHash(*file) : std::string();
  const std::string name = file ? file->filename().string() : "array " + std::to_string(index);
  std::vector<calibrate::MeasuredSequence> sequences;
  const py::list list = fields["sequences"];
  for (std::size_t s = 0; s < list.size(); ++s) {
    const py::dict fields_s = list[s];
    const auto onsets = fields_s["onsets_s"].cast<std::vector<double>>();
    const auto sigmas = fields_s["onset_uncertainty_s"].cast<std::vector<double>>();
    // Results of an older module have no incoming-flight uncertainties: none was stated then.
    std::vector<double> flight_sigmas(onsets.size(), 0.0);
    if (fields_s.contains("incoming_flight_uncertainty_s"))
      flight_sigmas = fields_s["incoming_flight_uncertainty_s"].cast<std::vector<double>>();
    calibrate::MeasuredSequence sequence;
    sequence.source = name + "#" + std::to_string(s + 1);
    if (file) sequence.path = *file;
    sequence.content_hash = hash;
    for (std::size_t i = 0; i < onsets.size() && i < sigmas.size(); ++i) {
      sequence.impacts.push_back(
          {onsets[i], sigmas[i], i > 0 && i < flight_sigmas.size() ? flight_sigmas[i] : 0.0});
    }
    // As LoadSequences: fewer impacts carry no restitution.
    if (sequence.impacts.size() >= 3) sequences.push_back(std::move(sequence));
  }
  if (sequences.empty()) {
    throw InputError(Describe(index) + " (" + name +
                     "): the analysis holds no bounce sequence of at least 3 impacts");
  }
  return sequences;
}

struct Inputs {
  std::vector<calibrate::MeasuredSequence> sequences;
  std::vector<std::filesystem::path> recordings;
  std::vector<std::size_t> input_of_sequence;  // index into `inputs` of each sequence
  std::size_t count = 0;                       // how many inputs were given
};

// A keyword that takes one number for every input or one per input in order: the numbers, none
// for None.
std::vector<double> OneOrPerInput(py::handle value, const char* keyword) {
  if (value.is_none()) return {};
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
    return {value.cast<double>()};
  }
  if (py::isinstance<py::sequence>(value) && !py::isinstance<py::str>(value)) {
    try {
      auto values = value.cast<std::vector<double>>();
      if (!values.empty()) return values;
    } catch (const py::cast_error&) {
    }
  }
  throw OptionError({keyword}, std::string(keyword) +
                                   " must be a number or a list of numbers (one per input, in "
                                   "order), got " +
                                   py::repr(value).cast<std::string>());
}

Inputs LoadInputs(py::handle inputs, double onset_uncertainty_s) {
  // One path or one analysis alone is a list of one.
  const py::list listed = IsPathLike(inputs) || py::isinstance<py::dict>(inputs)
                              ? py::list(py::make_tuple(inputs))
                              : py::list(py::reinterpret_borrow<py::object>(inputs));
  calibrate::SequenceInputOptions options;
  options.impact_times.default_uncertainty_s = onset_uncertainty_s;
  options.impact_times.Validate();
  Inputs loaded;
  for (std::size_t i = 0; i < listed.size(); ++i) {
    const py::handle item = listed[i];
    std::vector<calibrate::MeasuredSequence> read;
    if (IsPathLike(item)) {
      const auto path = ToPath(item, Describe(i));
      loaded.recordings.push_back(path);
      py::gil_scoped_release release;
      read = calibrate::LoadSequences({path}, options);
    } else if (py::isinstance<py::dict>(item) && item.cast<py::dict>().contains("sequences")) {
      read = SequencesFromAnalysis(item, i, loaded.recordings);
    } else {
      read.push_back(SequenceFromArray(item, i, onset_uncertainty_s));
    }
    loaded.sequences.insert(loaded.sequences.end(), read.begin(), read.end());
    loaded.input_of_sequence.insert(loaded.input_of_sequence.end(), read.size(), i);
  }
  loaded.count = listed.size();
  if (loaded.sequences.empty()) {
    throw ConfigError("no recording to fit; give at least one input");
  }
  return loaded;
}

std::map<std::string, calibrate::ParameterRange, std::less<>> RangesFromPython(py::handle ranges) {
  std::map<std::string, calibrate::ParameterRange, std::less<>> out;
  if (ranges.is_none()) return out;
  if (!py::isinstance<py::dict>(ranges)) {
    throw ConfigError("ranges must be a dict {name: (lower, upper[, log_scale])}");
  }
  for (const auto& [key, value] : ranges.cast<py::dict>()) {
    const auto name = py::str(key).cast<std::string>();
    if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
      throw ConfigError("ranges['" + name + "'] must be (lower, upper) or (lower, upper, " +
                        "log_scale), got " + py::repr(value).cast<std::string>());
    }
    const auto bounds = py::list(py::reinterpret_borrow<py::object>(value));
    if (bounds.size() != 2 && bounds.size() != 3) {
      throw ConfigError("ranges['" + name + "'] must be (lower, upper) or (lower, upper, " +
                        "log_scale), got " + py::repr(value).cast<std::string>());
    }
    calibrate::ParameterRange range;
    range.lower = bounds[0].cast<double>();
    range.upper = bounds[1].cast<double>();
    if (bounds.size() == 3) range.log_scale = bounds[2].cast<bool>();
    out[name] = range;
  }
  return out;
}

}  // namespace

void BindCalibrate(py::module_& module) {
  py::class_<CardSource, std::shared_ptr<CardSource>>(
      module, "_CardSource", "The fit a Calibration's material card is made from")
      .def(
          "card",
          [](const CardSource& source, std::optional<std::int64_t> created_at) {
            return FromJson(calibrate::ToJson(MakeCard(source, created_at)));
          },
          py::arg("created_at") = py::none())
      .def(
          "write_card",
          [](const CardSource& source, const std::filesystem::path& path,
             std::optional<std::int64_t> created_at) {
            const auto card = MakeCard(source, created_at);
            calibrate::WriteMaterialCard(path, card);
            return FromJson(calibrate::ToJson(card));
          },
          py::arg("path"), py::arg("created_at") = py::none());

  const calibrate::FitOptions defaults;
  module.def(
      "calibrate",
      [](py::object inputs, py::object law, py::object parameters,
         std::vector<std::string> fitted_parameters, py::object ranges,
         std::optional<std::string> ball, std::optional<double> diameter_m,
         std::optional<double> density_kg_per_m3, std::optional<double> mass_kg,
         py::object drop_height_m, py::object drop_height_uncertainty_m,
         std::optional<double> contact_duration_s, double gravity_mps2,
         const std::string& integrator, std::optional<double> time_step_s,
         std::optional<double> steps_per_contact, bool fixed_step_grid, bool drag,
         double drag_coefficient, double air_density_kg_per_m3, const std::string& objective,
         std::optional<int> first_n, int max_intervals, const std::string& optimizer,
         int max_evaluations, int global_evaluations, double confidence_level, int threads,
         bool analytic_check, double onset_uncertainty_s) {
        auto source = std::make_shared<CardSource>();
        calibrate::FitOptions& options = source->options;
        dem::DropOptions& drop = options.drop;
        drop.law = LawFromPython(law, parameters);
        const auto given_ball =
            BallFromArguments({ball, diameter_m, density_kg_per_m3, mass_kg}, /*complete=*/true);
        if (given_ball) drop.ball = *given_ball;
        options.ball_given = given_ball.has_value();
        options.ball_preset = ball.value_or("");
        // One height (or uncertainty) is every input's; a list gives each input its own, in
        // order, as the command line's repeated --drop-height-m does.
        const auto heights = OneOrPerInput(drop_height_m, "drop_height_m");
        const auto height_sigmas =
            OneOrPerInput(drop_height_uncertainty_m, "drop_height_uncertainty_m");
        calibrate::ValidateDropHeights(heights, height_sigmas);
        const bool height_per_input = heights.size() > 1 || height_sigmas.size() > 1;
        if (heights.size() == 1) drop.drop_height_m = heights.front();
        options.drop_height_given = heights.size() == 1;
        drop.gravity_mps2 = gravity_mps2;
        if (contact_duration_s) {
          const std::string elastic(calibrate::ElasticParameterName(drop.law.kind));
          if (!parameters.is_none() && parameters.cast<py::dict>().contains(elastic)) {
            throw OptionError({"contact_duration_s"},
                              "contact_duration_s and parameters['" + elastic +
                                  "'] both set the stiffness; give one of them");
          }
        }
        options.contact_duration_s = contact_duration_s;
        drop.drag = {.enabled = drag,
                     .drag_coefficient = drag_coefficient,
                     .air_density_kg_per_m3 = air_density_kg_per_m3};
        drop.integrator = dem::IntegratorFromString(integrator);
        drop.time_step_s = time_step_s;
        if (steps_per_contact) drop.steps_per_contact = *steps_per_contact;
        drop.fixed_step_grid = fixed_step_grid;
        options.fitted_parameters = std::move(fitted_parameters);
        options.ranges = RangesFromPython(ranges);
        options.objective = calibrate::FitObjectiveFromString(objective);
        if (first_n) {
          options.first_n = *first_n;
          options.first_n_given = true;
        }
        options.max_intervals = max_intervals;
        options.minimizer.local_method = calibrate::LocalMethodFromString(optimizer);
        options.minimizer.max_evaluations = max_evaluations;
        options.minimizer.global_evaluations = global_evaluations;
        options.uncertainty.confidence_level = confidence_level;
        options.uncertainty.threads = threads;
        if (height_sigmas.size() == 1 && !height_per_input) {
          options.uncertainty.drop_height_uncertainty_m = height_sigmas.front();
        }
        options.analytic_check = analytic_check;

        // The settings checked before any input is read, as on the command line, naming the
        // keywords (the library's field names).
        options.ValidateSettings();
        Inputs loaded = LoadInputs(inputs, onset_uncertainty_s);
        if (height_per_input) {
          const auto per_input = [&](const std::vector<double>& values, const char* keyword) {
            if (values.size() > 1 && values.size() != loaded.count) {
              throw OptionError({keyword}, std::string(keyword) + " gives " +
                                               std::to_string(values.size()) + " values for " +
                                               std::to_string(loaded.count) +
                                               " inputs; give one for all, or one per input");
            }
          };
          per_input(heights, "drop_height_m");
          per_input(height_sigmas, "drop_height_uncertainty_m");
          if (heights.empty()) {
            throw OptionError({"drop_height_m", "drop_height_uncertainty_m"},
                              "drop_height_uncertainty_m per input needs drop_height_m");
          }
          for (std::size_t s = 0; s < loaded.sequences.size(); ++s) {
            const std::size_t input = loaded.input_of_sequence[s];
            const auto pick = [&](const std::vector<double>& values) {
              return values.size() == 1 ? values.front() : values[input];
            };
            // Every drop in an input was released from its height.
            loaded.sequences[s].drop_height_m = pick(heights);
            loaded.sequences[s].drop_height_uncertainty_m =
                height_sigmas.empty() ? 0.0 : pick(height_sigmas);
          }
        }
        source->recordings = std::move(loaded.recordings);
        {
          py::gil_scoped_release release;
          source->summary = calibrate::Fit(loaded.sequences, options);
        }
        py::object result = NewResult("Calibration");
        result.attr("update")(FromJson(calibrate::ToJson(source->summary)));
        py::setattr(result, "_card_source", py::cast(source));
        return result;
      },
      py::arg("inputs"), py::kw_only(), py::arg("law") = "walton-braun",
      py::arg("parameters") = py::none(), py::arg("fitted_parameters") = std::vector<std::string>{},
      py::arg("ranges") = py::none(), py::arg("ball") = py::none(),
      py::arg("diameter_m") = py::none(), py::arg("density_kg_per_m3") = py::none(),
      py::arg("mass_kg") = py::none(), py::arg("drop_height_m") = py::none(),
      py::arg("drop_height_uncertainty_m") = defaults.uncertainty.drop_height_uncertainty_m,
      py::arg("contact_duration_s") = py::none(),
      py::arg("gravity_mps2") = defaults.drop.gravity_mps2,
      py::arg("integrator") = std::string(dem::ToString(defaults.drop.integrator)),
      py::arg("time_step_s") = py::none(), py::arg("steps_per_contact") = py::none(),
      py::arg("fixed_step_grid") = defaults.drop.fixed_step_grid,
      py::arg("drag") = defaults.drop.drag.enabled,
      py::arg("drag_coefficient") = defaults.drop.drag.drag_coefficient,
      py::arg("air_density_kg_per_m3") = defaults.drop.drag.air_density_kg_per_m3,
      py::arg("objective") = std::string(calibrate::ToString(defaults.objective)),
      py::arg("first_n") = py::none(), py::arg("max_intervals") = defaults.max_intervals,
      py::arg("optimizer") = std::string(calibrate::ToString(defaults.minimizer.local_method)),
      py::arg("max_evaluations") = defaults.minimizer.max_evaluations,
      py::arg("global_evaluations") = defaults.minimizer.global_evaluations,
      py::arg("confidence_level") = defaults.uncertainty.confidence_level,
      py::arg("threads") = defaults.uncertainty.threads,
      py::arg("analytic_check") = defaults.analytic_check,
      py::arg("onset_uncertainty_s") = calibrate::ImpactTimesOptions{}.default_uncertainty_s,
      R"doc(Fit a contact law's damping so single-ball DEM drops reproduce measured bounce
sequences (calibrate::Fit): what `bouncecal calibrate --json` writes.

inputs: a path or a list of them (recordings, impact-time .csv, `bouncecal analyze --json`
    files), analyze() results, 1-D numpy arrays of onset times in s (each with
    onset_uncertainty_s) or (n, 2) arrays of onsets and their one-sigma uncertainties; all are
    fitted jointly.
law, parameters: the law and its fixed parameters / start values, as for simulate_drop.
fitted_parameters: names to fit (default: the law's damping parameters); ranges: {name:
    (lower, upper[, log_scale])} overriding the default search ranges.
ball: a preset name, or diameter_m with density_kg_per_m3 or mass_kg. Needed for a material
    card, with drag and with the Hertz laws; otherwise the drops use the 1 cm steel reference.
drop_height_m: release height of the ball's lowest point in m, one for every input or a list
    with one per input in order (drop_height_uncertainty_m likewise); unset, e_1 and eta_1 are
    not computed and the drops start from the first measured bounce apex.
contact_duration_s: sets the law's stiffness so the simulated contact lasts this long at the
    drop's impact speed (needs the ball), as `bouncecal calibrate --contact-duration-s`.
The other keywords are calibrate::FitOptions' (bouncecal/calibrate/fit.h) and the options of
`bouncecal calibrate` of the same name: objective (mean-energy-loss, intervals, heights),
optimizer (bobyqa, cobyla, nelder-mead), confidence_level, ...

Returns a Calibration (a Result with the JSON's fields: parameters, confidence_interval,
uncertainty with the uncertainty model's description, analytic with the check against
eta = 2 gamma / (1 + gamma), ...) whose card() and write_card(path) give the material card.)doc");
}

}  // namespace bouncecal::python
