// The shipped paper-004 scenes (Cheng, Guo & Lai 1999) against the paper, on short runs: the
// full runs and the comparison with the paper's steady values are in docs/packing.md.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::dem {
namespace {

Scene ShippedScene(const std::string& name) {
  return LoadScene(std::filesystem::path(BOUNCECAL_SOURCE_DIR) / "samples/scenes" /
                   (name + ".json"));
}

double WindowAreaFractionAt(const std::string& name, double time_s) {
  PackOptions options;
  options.threads = 1;
  options.duration_s = time_s;
  const PackSummary summary = RunPacking(ShippedScene(name), options);
  EXPECT_EQ(summary.stop_reason, PackStopReason::kDuration) << summary.message;
  return summary.packing_density;
}

// Paper 004 section 3.1 (docs/physics.md section 3): at t = 0.0475 s the window's area fraction is
// 0.6894, the bottom settled and the top still loose. This is the sedimentation under gravity
// damped to (1 - alpha) g plus the first contacts, before the slow stage the paper reaches 0.8236
// in and ours does not (docs/packing.md). Tolerance 0.03: over insertion seeds 1-5 the scene gives
// 0.665-0.690 at that time (the window holds about 120 disks, one disk is 0.5 % of it, and the
// paper's random start is not ours); alpha = 0.9 instead of 0.7 gives 0.632 and fails.
TEST(Paper004Scene, AreaFractionAtTheIntermediateTimeMatchesThePaper) {
  EXPECT_NEAR(WindowAreaFractionAt("paper004_disks_friction_vdw", 0.0475), 0.6894, 0.03);
}

// Paper 004 section 3.2: in the binary mixture each added interaction loosens the structure,
// condition 1 (normal force only) > 2 (+ friction 0.364 and rotation) > 3 (+ van der Waals).
// At 0.1 s the three differ by 0.03 and 0.09, several times the seed-to-seed spread of the
// window fraction (standard deviation 0.008 over seeds 1-5 of the monodisperse scene).
TEST(Paper004Scene, FrictionThenCohesionLoosenTheBinaryPacking) {
  const double normal_only = WindowAreaFractionAt("paper004_binary_c1", 0.1);
  const double friction = WindowAreaFractionAt("paper004_binary_c2", 0.1);
  const double cohesion = WindowAreaFractionAt("paper004_binary_c3", 0.1);
  EXPECT_GT(normal_only, friction);
  EXPECT_GT(friction, cohesion);
}

}  // namespace
}  // namespace bouncecal::dem
