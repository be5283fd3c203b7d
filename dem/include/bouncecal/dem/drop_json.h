#ifndef BOUNCECAL_DEM_DROP_JSON_H_
#define BOUNCECAL_DEM_DROP_JSON_H_

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "bouncecal/dem/drop.h"

namespace bouncecal::dem {

// The format of a simulated drop (docs/json.md, docs/schema/drop.schema.json).
inline constexpr std::string_view kDropFormat = "bouncecal-drop/1";

// The drop document `bouncecal simulate drop --json` writes and `bouncecal.simulate_drop`
// returns (with its trajectory added): the impacts, why the drop stopped, the steps and the
// set-up that produced them. Written once, here, for both.
nlohmann::json ToJson(const DropResult& result, const DropOptions& options);

// The trajectory as CSV (time_s,height_m,velocity_mps), `simulate drop --trajectory`.
std::string TrajectoryCsv(const DropResult& result);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_DROP_JSON_H_
