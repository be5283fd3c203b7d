#include "pack_results.h"

#include <fmt/core.h>

#include <cmath>
#include <sstream>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/packing_json.h"
#include "output_target.h"

namespace bouncecal::apps {
namespace {

bool Finite(const dem::HistoryPoint& h) {
  return std::isfinite(h.time_s) && std::isfinite(h.packing_density) &&
         std::isfinite(h.kinetic_energy_j) && std::isfinite(h.max_speed_mps);
}

}  // namespace

void WritePackTables(const std::filesystem::path& dir, const dem::Scene& scene,
                     const dem::PackSummary& s) {
  std::ostringstream history;
  history << "time_s,packing_density,kinetic_energy_j,max_speed_mps,particles\n";
  for (const auto& h : s.history) {
    // A run that blew up ends in inf/nan rows (its kinetic energy overflows before the engine
    // notices); the history stops at the last row that is a number throughout.
    if (!Finite(h)) break;
    history << fmt::format("{:.6g},{:.6f},{:.6g},{:.6g},{}\n", h.time_s, h.packing_density,
                           h.kinetic_energy_j, h.max_speed_mps, h.particles);
  }
  WriteFileAtomically(dir / "history.csv", history.str());
  // The state an unstable run stopped in is not a packing: RunPacking measures no profile or
  // coordination of it and its positions may be inf/nan, so none of the final-state tables is
  // written (RemoveEarlierOutputs already took away those of an earlier run).
  if (s.stop_reason == dem::PackStopReason::kUnstable) return;
  std::ostringstream profile;
  profile << "height_m,density\n";
  for (std::size_t b = 0; b < s.profile.height_m.size(); ++b) {
    profile << fmt::format("{:.6g},{:.6f}\n", s.profile.height_m[b], s.profile.density[b]);
  }
  WriteFileAtomically(dir / "profile.csv", profile.str());
  std::ostringstream coordination;
  coordination << "coordination,particles,fraction\n";
  for (std::size_t z = 0; z < s.coordination.histogram.size(); ++z) {
    const double fraction =
        s.coordination.particles > 0
            ? static_cast<double>(s.coordination.histogram[z]) / s.coordination.particles
            : 0.0;
    coordination << fmt::format("{},{},{:.6f}\n", z, s.coordination.histogram[z], fraction);
  }
  WriteFileAtomically(dir / "coordination.csv", coordination.str());
  std::ostringstream particles;
  particles << "x_m,y_m" << (scene.dimension == 3 ? ",z_m" : "")
            << ",diameter_m,species,vx_mps,vy_mps" << (scene.dimension == 3 ? ",vz_mps" : "")
            << "\n";
  const auto& f = s.final_state;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto& x = f.position_m[i];
    const auto& v = f.velocity_mps[i];
    if (scene.dimension == 3) {
      particles << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{},{:.6g},{:.6g},{:.6g}\n", x[0], x[1],
                               x[2], 2 * f.radius_m[i], f.species[i], v[0], v[1], v[2]);
    } else {
      particles << fmt::format("{:.9g},{:.9g},{:.9g},{},{:.6g},{:.6g}\n", x[0], x[1],
                               2 * f.radius_m[i], f.species[i], v[0], v[1]);
    }
  }
  WriteFileAtomically(dir / "particles.csv", particles.str());
}

void WritePackSummaryJson(const std::filesystem::path& dir, const std::filesystem::path& json,
                          const dem::Scene& scene, const dem::PackSummary& summary) {
  const std::string text = dem::ToJson(scene, summary).dump(2) + "\n";
  WriteFileAtomically(dir / "summary.json", text);
  if (!json.empty()) WriteTextOutput(json, text);
}

}  // namespace bouncecal::apps
