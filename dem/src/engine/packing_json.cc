#include "bouncecal/dem/packing_json.h"

#include <fmt/core.h>

#include <cmath>
#include <string>

#include "bouncecal/option_error.h"

namespace bouncecal::dem {
namespace {

// nlohmann would write a non-finite double as null anyway; said here, so the rule is visible.
nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json ToJson(const Scene& scene, const PackSummary& s) {
  const bool measured = s.stop_reason != PackStopReason::kUnstable;
  nlohmann::json j;
  j["format"] = kPackFormat;
  j["scene"] = scene.source.string();
  j["physics"] = s.physics;
  j["stop_reason"] = std::string(ToString(s.stop_reason));
  j["message"] = s.message;
  j["state_digest"] = fmt::format("{:016x}", s.state_digest);
  j["boiling"] = s.boiling;
  // An unstable run is never measured (RunPacking leaves these at 0): a 0 would read as an empty
  // container, so they are null.
  j["packing_density"] = measured ? FiniteOrNull(s.packing_density) : nullptr;
  j["packing_density_by_count"] = measured ? FiniteOrNull(s.packing_density_by_count) : nullptr;
  j["mean_coordination"] = measured ? FiniteOrNull(s.coordination.mean) : nullptr;
  j["coordination_histogram"] =
      measured ? nlohmann::json(s.coordination.histogram) : nlohmann::json(nullptr);
  j["coordination_particles"] =
      measured ? nlohmann::json(s.coordination.particles) : nlohmann::json(nullptr);
  j["particles"] = s.particles;
  j["particles_not_inserted"] = s.particles_not_inserted;
  j["steps"] = s.steps;
  j["time_step_s"] = FiniteOrNull(s.time_step_s);
  j["time_step_limit_s"] = FiniteOrNull(s.time_step_limit_s);
  j["tangential_time_step_limit_s"] = FiniteOrNull(s.tangential_time_step_limit_s);
  j["warnings"] = s.warnings;
  j["simulated_s"] = FiniteOrNull(s.simulated_s);
  // The energy of a blown-up state measures the failure, not the packing.
  j["kinetic_energy_j"] = measured ? FiniteOrNull(s.kinetic_energy_j) : nullptr;
  j["neighbor_rebuilds"] = s.neighbor_rebuilds;
  j["threads"] = s.threads;
  j["contact_precision"] = s.single_precision_contacts ? "single" : "double";
  j["wall_s"] = FiniteOrNull(s.wall_s);
  j["total_wall_s"] = FiniteOrNull(s.total_wall_s);
  j["particle_steps_per_s"] = FiniteOrNull(s.particle_steps_per_s);
  if (scene.dimension == 3) {
    j["band_m"] = {scene.measurement.band_min_m, scene.measurement.band_max_m};
  } else {
    j["window_m"] = {{scene.measurement.window_min_m[0], scene.measurement.window_min_m[1]},
                     {scene.measurement.window_max_m[0], scene.measurement.window_max_m[1]}};
  }
  return j;
}

void CheckDurationOverride(const Scene& scene, std::optional<double> duration_s) {
  if (!duration_s) return;
  if (!(*duration_s >= 0 && *duration_s <= 1e6)) {
    throw OptionError({"duration_s"},
                      fmt::format("duration_s must be in [0, 1e6] s, got {:g}", *duration_s));
  }
  if (*duration_s > 0 && *duration_s < scene.time_step_s) {
    throw OptionError(
        {"duration_s"},
        fmt::format("duration_s {:g} s is below the scene's time_step_s ({:g} s in {}), so no "
                    "step would run; give at least {:g} s, or 0 to measure the start state",
                    *duration_s, scene.time_step_s, scene.source.string(), scene.time_step_s));
  }
}

}  // namespace bouncecal::dem
