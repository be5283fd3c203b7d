#include "arguments.h"

#include <Python.h>

#include <ctime>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/calibrate/card_creation_time.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/contact_law_kind.h"
#include "bouncecal/error.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

std::string TypeName(py::handle value) {
  return py::type::of(value).attr("__name__").cast<std::string>();
}

double ParameterValue(py::handle value, const std::string& name) {
  // float() would also parse strings; a law parameter is a number.
  if (py::isinstance<py::str>(value) || py::isinstance<py::bool_>(value) ||
      !(py::hasattr(value, "__float__") || py::hasattr(value, "__index__"))) {
    throw ConfigError("parameters['" + name + "'] must be a number in the unit its name states, " +
                      "got a " + TypeName(value));
  }
  const double number = PyFloat_AsDouble(value.ptr());
  if (PyErr_Occurred()) throw py::error_already_set();
  return number;
}

}  // namespace

dem::ContactLawConfig LawFromPython(py::handle law, py::handle parameters, bool validate) {
  dem::ContactLawConfig config;
  if (py::isinstance<py::str>(law)) {
    config.kind = dem::ContactLawKindFromString(law.cast<std::string>());
  } else if (py::isinstance<py::dict>(law)) {
    // The reader is the material card's, whose problems are those of a file (InputError); here
    // the dict is an argument.
    try {
      config = dem::ContactLawConfigFromJson(ToJson(law, "law"), "law");
    } catch (const InputError& error) {
      throw ConfigError(error.what());
    }
  } else {
    throw ConfigError("law must be a law name (" + dem::ContactLawNames() +
                      ") or a {'law': ..., 'parameters': {...}} dict, got a " + TypeName(law));
  }
  if (!parameters.is_none()) {
    if (!py::isinstance<py::dict>(parameters)) {
      throw ConfigError("parameters must be a dict {name: value}, e.g. {'gamma_n': 0.4}, got a " +
                        TypeName(parameters));
    }
    for (const auto& [key, value] : parameters.cast<py::dict>()) {
      const auto name = py::str(key).cast<std::string>();
      config.parameters[name] = ParameterValue(value, name);
    }
  }
  if (validate) config.Validate();
  return config;
}

std::optional<dem::Ball> BallFromArguments(const BallArguments& arguments, bool complete) {
  const bool explicit_ball =
      arguments.diameter_m || arguments.density_kg_per_m3 || arguments.mass_kg;
  if (arguments.preset) {
    if (explicit_ball) {
      throw ConfigError("ball='" + *arguments.preset +
                        "' names a preset; give either it or diameter_m with density_kg_per_m3 "
                        "or mass_kg, not both");
    }
    return calibrate::FindBallPreset(*arguments.preset).ToBall();
  }
  if (!explicit_ball) return std::nullopt;
  if (arguments.density_kg_per_m3 && arguments.mass_kg) {
    throw ConfigError("density_kg_per_m3 and mass_kg both give the ball's mass; give one of them");
  }
  if (complete && !arguments.diameter_m) {
    throw ConfigError(
        "density_kg_per_m3 or mass_kg needs diameter_m (the ball's size), or use ball=NAME");
  }
  if (complete && !arguments.density_kg_per_m3 && !arguments.mass_kg) {
    throw ConfigError(
        "diameter_m needs density_kg_per_m3 or mass_kg (the ball's mass), or use ball=NAME");
  }
  dem::Ball ball;  // else completed with the 1 cm steel ball
  if (arguments.diameter_m) ball.diameter_m = *arguments.diameter_m;
  if (arguments.density_kg_per_m3) ball.density_kg_per_m3 = *arguments.density_kg_per_m3;
  ball.mass_kg = arguments.mass_kg;
  ball.Validate();
  return ball;
}

std::time_t CardCreationTime() {
  // The command line's rule, so a card made from Python under SOURCE_DATE_EPOCH is as
  // reproducible as one made by `bouncecal calibrate --card`.
  return calibrate::CardCreationTimeFromEnvironment("unset it or pass created_at=SECONDS");
}

}  // namespace bouncecal::python
