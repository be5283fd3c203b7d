#include "bouncecal/dem/drop_json.h"

#include <fmt/core.h>

#include "bouncecal/dem/contact_law_json.h"

namespace bouncecal::dem {

nlohmann::json ToJson(const DropResult& result, const DropOptions& options) {
  nlohmann::json impacts = nlohmann::json::array();
  for (const DropImpact& impact : result.impacts) {
    impacts.push_back({{"time_s", impact.time_s},
                       {"restitution", impact.restitution},
                       {"energy_loss", impact.energy_loss},
                       {"contact_duration_s", impact.contact_duration_s},
                       {"max_overlap_m", impact.max_overlap_m},
                       {"speed_in_mps", impact.speed_in_mps},
                       {"speed_out_mps", impact.speed_out_mps},
                       {"released", impact.released}});
  }
  return {{"format", kDropFormat},
          {"impacts", impacts},
          {"stop_reason", std::string(ToString(result.stop_reason))},
          {"stop_detail", result.stop_detail},
          {"steps", result.steps},
          {"time_step_s", result.time_step_s},
          {"stability_limit_s", result.stability_limit_s},
          {"integrator", std::string(ToString(options.integrator))},
          {"contact_law", ToJson(options.law)},
          {"ball",
           {{"diameter_m", options.ball.diameter_m},
            {"density_kg_per_m3", options.ball.DensityKgPerM3()},
            {"mass_kg", options.ball.MassKg()}}},
          {"drop_height_m", options.drop_height_m},
          {"gravity_mps2", options.gravity_mps2}};
}

std::string TrajectoryCsv(const DropResult& result) {
  std::string csv = "time_s,height_m,velocity_mps\n";
  for (const TrajectoryPoint& point : result.trajectory) {
    csv += fmt::format("{:.9g},{:.9g},{:.9g}\n", point.time_s, point.height_m, point.velocity_mps);
  }
  return csv;
}

}  // namespace bouncecal::dem
