#ifndef BOUNCECAL_DEM_PACKING_JSON_H_
#define BOUNCECAL_DEM_PACKING_JSON_H_

#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::dem {

// The format of a packing summary (docs/json.md, docs/schema/pack.schema.json).
inline constexpr std::string_view kPackFormat = "bouncecal-pack/1";

// The summary `bouncecal pack` writes (summary.json, --json) and `bouncecal.pack` returns (with
// its history, profile and final state added), written once, here, for both. A quantity that
// was not measured is null: the measures of a run that became unstable (never measured), and any
// value that is not a finite number.
nlohmann::json ToJson(const Scene& scene, const PackSummary& summary);

// A duration override that would run no step (positive, below the scene's time step) reports
// the start state as if it were the result: refused, naming duration_s (OptionError). 0 asks
// for the start state and is allowed; so is no override.
void CheckDurationOverride(const Scene& scene, std::optional<double> duration_s);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_PACKING_JSON_H_
