// The shipped paper-004 scenes (Cheng, Guo & Lai 1999) against the paper, on short runs: the
// full runs and the comparison with the paper's steady values are in docs/packing.md.

#include <gtest/gtest.h>

#include <cstdint>
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

PackSummary RunShipped(const std::string& name, double duration_s, std::uint64_t seed) {
  Scene scene = ShippedScene(name);
  scene.insertion.seed = seed;
  PackOptions options;
  options.threads = 1;
  options.duration_s = duration_s;
  PackSummary summary = RunPacking(scene, options);
  EXPECT_EQ(summary.stop_reason, PackStopReason::kDuration) << summary.message;
  return summary;
}

double WindowAreaFractionAt(const std::string& name, double time_s) {
  return RunShipped(name, time_s, ShippedScene(name).insertion.seed).packing_density;
}

// Paper 004 section 3.1: friction 0.364 and van der Waals settle at area fraction 0.8236 with mean
// coordination 3.609. The shipped set-up (docs/packing.md, "The shipped set-up") must give both
// as the mean over insertion seeds 1-5, within the 0.02 and 0.3. Those are 6 and 11
// standard errors of the five-seed mean (seed sd 0.007 and 0.06), so seed noise cannot fail the
// test, while the readings with local damping miss by more than 0.03 (on all forces 0.691-0.792,
// on contact forces only 0.686-0.783) and so does the frictionless packing (0.856).
TEST(Paper004Scene, FrictionAndCohesionSettleAtThePapersAreaFractionAndCoordination) {
  constexpr int kSeeds = 5;
  double area_fraction = 0;
  double coordination = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const PackSummary summary = RunShipped("paper004_disks_friction_vdw", 0.2, seed);
    area_fraction += summary.packing_density / kSeeds;
    coordination += summary.coordination.mean / kSeeds;
  }
  EXPECT_NEAR(area_fraction, 0.8236, 0.02);
  EXPECT_NEAR(coordination, 3.609, 0.3);
}

// The literal reading (alpha = 0.7 on the whole force, gravity included) sediments at 0.3 g: at
// t = 0.0475 s the window holds the paper's 0.6894, bottom settled and top still loose, although
// it then settles loose (0.691, docs/packing.md). Tolerance 0.03: over insertion seeds 1-5 it gives
// 0.665-0.690 at that time (the window holds about 120 disks, one disk is 0.5 % of it, and the
// paper's random start is not ours); alpha = 0.9 instead of 0.7 gives 0.632 and fails, and the
// shipped set-up (fall at g) is settled at 0.82 by then.
TEST(Paper004Scene, LiteralReadingMatchesThePapersIntermediateAreaFraction) {
  EXPECT_NEAR(WindowAreaFractionAt("paper004_disks_friction_vdw_literal", 0.0475), 0.6894, 0.03);
}

// Paper 004 section 3.2: in the binary mixture friction loosens the structure, condition 1
// (normal force only) > 2 (+ friction 0.364 and rotation). At 0.1 s they differ by 0.034-0.067 for
// each of insertion seeds 1-5, so a margin of 0.02 holds for any of them and fails when friction
// does not act (condition 2 then packs like 1).
// The roughness-limited cohesion of the shipped set-up (condition 3) does not loosen it further
// beyond the seed spread (0.823 +- 0.015 against 0.813 +- 0.007 at 0.2 s), so no order is
// asserted for it.
TEST(Paper004Scene, FrictionLoosensTheBinaryPacking) {
  const double normal_only = WindowAreaFractionAt("paper004_binary_c1", 0.1);
  const double friction = WindowAreaFractionAt("paper004_binary_c2", 0.1);
  EXPECT_GT(normal_only, friction + 0.02);
}

}  // namespace
}  // namespace bouncecal::dem
