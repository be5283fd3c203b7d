#ifndef BOUNCECAL_DEM_CONTACT_LAW_JSON_H_
#define BOUNCECAL_DEM_CONTACT_LAW_JSON_H_

#include <nlohmann/json.hpp>
#include <string_view>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::dem {

// {"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}}
// Values are plain numbers in the SI unit implied by the parameter name (ParameterSpec::unit);
// "parameters" may be omitted or partial (defaults fill in). The object always comes from a file
// (material card, scene, export material), so every problem is an InputError (exit status 2,
// like any other malformed field of that file) prefixed by `context` (e.g. "scene.json:
// material"): unknown keys are rejected with their name; wrong types, non-finite or
// out-of-range values name the key and the valid range.
ContactLawConfig ContactLawConfigFromJson(const nlohmann::json& object, std::string_view context);

// Writes every parameter of the law (defaults included), so a card states the full law.
nlohmann::json ToJson(const ContactLawConfig& config);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAW_JSON_H_
