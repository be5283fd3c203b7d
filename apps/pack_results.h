#ifndef BOUNCECAL_APPS_PACK_RESULTS_H_
#define BOUNCECAL_APPS_PACK_RESULTS_H_

#include <filesystem>
#include <string>

#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::apps {

// pack's tables in the output folder: history.csv and, unless the run was unstable, profile.csv,
// coordination.csv and particles.csv (docs/scenes.md).
void WritePackTables(const std::filesystem::path& dir, const dem::Scene& scene,
                     const dem::PackSummary& summary);

// summary.json in the output folder and, when given, the --json file ("-": stdout): the one
// serializer, dem::ToJson.
void WritePackSummaryJson(const std::filesystem::path& dir, const std::filesystem::path& json,
                          const dem::Scene& scene, const dem::PackSummary& summary);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PACK_RESULTS_H_
