#include "bouncecal/dem/contact_law_json.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {

ContactLawConfig ContactLawConfigFromJson(const nlohmann::json& object, std::string_view context) {
  const auto fail = [&](const std::string& what) {
    throw InputError(fmt::format("{}: {}", context, what));
  };
  if (!object.is_object()) {
    fail(
        "the contact law must be a JSON object like {\"law\": \"walton-braun\", \"parameters\": "
        "{...}}");
  }
  ContactLawConfig config;
  bool has_law = false;
  for (const auto& [key, value] : object.items()) {
    if (key == "law") {
      if (!value.is_string()) fail("\"law\" must be a string naming one of: " + ContactLawNames());
      try {
        config.kind = ContactLawKindFromString(value.get<std::string>());
      } catch (const ConfigError& error) {
        fail(error.what());
      }
      has_law = true;
    } else if (key != "parameters") {
      fail(fmt::format("unknown key \"{}\" in the contact law; valid keys: law, parameters", key));
    }
  }
  if (!has_law) fail("the contact law has no \"law\" key; name one of: " + ContactLawNames());
  if (object.contains("parameters")) {
    const nlohmann::json& parameters = object.at("parameters");
    if (!parameters.is_object()) fail("\"parameters\" must be an object of name: number");
    for (const auto& [key, value] : parameters.items()) {
      if (!value.is_number()) {
        fail(fmt::format("parameter \"{}\" must be a number (SI units), not {}", key,
                         value.type_name()));
      }
      config.parameters[key] = value.get<double>();
    }
  }
  try {
    MakeContactLaw(config);  // range checks and cross-parameter rules
  } catch (const ConfigError& error) {
    fail(error.what());
  }
  return config;
}

nlohmann::json ToJson(const ContactLawConfig& config) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const ParameterSpec& spec : ParameterSpecs(config.kind)) {
    parameters[std::string(spec.name)] = config.Get(spec.name);
  }
  return {{"law", std::string(ToString(config.kind))}, {"parameters", parameters}};
}

}  // namespace bouncecal::dem
