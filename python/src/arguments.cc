#include "arguments.h"

#include <Python.h>

#include <charconv>
#include <cstdlib>
#include <ctime>
#include <string_view>

#include "bouncecal/calibrate/ball_preset.h"
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
  // The command line's rule (apps/card_creation_time.cc), so a card made from Python under
  // SOURCE_DATE_EPOCH is as reproducible as one made by `bouncecal calibrate --card`.
  constexpr long long kLastFourDigitYearSecond = 253402300799LL;  // 9999-12-31T23:59:59Z
  const char* value = std::getenv("SOURCE_DATE_EPOCH");
  if (value == nullptr) return std::time(nullptr);
  const std::string_view text = value;
  long long seconds = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seconds);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || seconds < 0 ||
      seconds > kLastFourDigitYearSecond) {
    throw ConfigError("SOURCE_DATE_EPOCH='" + std::string(text) +
                      "' is not a whole number of seconds since 1970-01-01 UTC in 0.." +
                      std::to_string(kLastFourDigitYearSecond) +
                      "; unset it or pass created_at=SECONDS");
  }
  return static_cast<std::time_t>(seconds);
}

}  // namespace bouncecal::python
