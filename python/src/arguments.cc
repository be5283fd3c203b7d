#include "arguments.h"

#include <Python.h>

#include <ctime>

#include "bouncecal/calibrate/ball_choice.h"
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

std::optional<dem::Ball> BallFromArguments(const calibrate::BallChoice& arguments, bool complete) {
  return calibrate::ResolveBall(arguments, complete ? calibrate::BallCompletion::kAsGiven
                                                    : calibrate::BallCompletion::kPaperBall);
}

std::time_t CardCreationTime() {
  // The command line's rule, so a card made from Python under SOURCE_DATE_EPOCH is as
  // reproducible as one made by `bouncecal calibrate --card`.
  return calibrate::CardCreationTimeFromEnvironment("unset it or pass created_at=SECONDS");
}

}  // namespace bouncecal::python
