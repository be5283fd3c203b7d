#include "bouncecal/calibrate/trajectory_compare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

TEST(MeasuredTrajectory, ArcsPeakAtTheBounceHeights) {
  // Impacts of a ball with e = 0.7 from 0.2 m: the arc after impact k peaks at g dt_k^2 / 8.
  const double g = 9.81;
  std::vector<double> onsets = {5.0};
  double flight = DropFlightTime(0.2, g);
  for (int k = 0; k < 4; ++k) {
    flight *= 0.7;
    onsets.push_back(onsets.back() + flight);
  }
  const auto curve = MeasuredTrajectory(onsets, 0.2, g, 1e-5);
  EXPECT_NEAR(curve.height_m.front(), 0.2, 1e-12);
  const double first_flight = onsets[1] - onsets[0];
  double peak = 0;
  for (size_t i = 0; i < curve.time_s.size(); ++i) {
    if (curve.time_s[i] < std::sqrt(2 * 0.2 / g) + first_flight) {
      if (curve.time_s[i] > std::sqrt(2 * 0.2 / g)) peak = std::max(peak, curve.height_m[i]);
    }
  }
  // 10 us sampling of a parabola: the sampled peak is within g (5 us)^2 / 2 of the true one.
  EXPECT_NEAR(peak, g * first_flight * first_flight / 8, 1e-9);
}

TEST(RmsHeightError, IsZeroForIdenticalCurvesAndTheOffsetForAShiftedOne) {
  HeightCurve a{{0, 1, 2, 3}, {1, 2, 3, 4}};
  EXPECT_NEAR(RmsHeightError(a, a), 0, 1e-15);
  HeightCurve b{{0, 1, 2, 3}, {1.5, 2.5, 3.5, 4.5}};
  EXPECT_NEAR(RmsHeightError(a, b), 0.5, 1e-12);
}

TEST(CompareTrajectories, TheGeneratingLawHasTheSmallestError) {
  dem::DropOptions drop;
  drop.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.5}}};
  drop.integrator = dem::Integrator::kExact;
  drop.max_impacts = 8;
  std::vector<double> onsets;
  for (const auto& impact : dem::SimulateDrop(drop).impacts) onsets.push_back(impact.time_s);
  TrajectoryCompareOptions options;
  for (double gamma : {0.3, 0.5, 0.7})
    options.laws.push_back({dem::ContactLawKind::kWaltonBraun, {{"gamma_n", gamma}}});
  const auto summary = CompareTrajectories(onsets, options);
  ASSERT_EQ(summary.simulated.size(), 3u);
  EXPECT_LT(summary.simulated[1].rms_height_error_m, summary.simulated[0].rms_height_error_m);
  EXPECT_LT(summary.simulated[1].rms_height_error_m, summary.simulated[2].rms_height_error_m);
  // Same law, verlet vs exact onsets and 0.5 ms sampling: within 1 mm of a 0.2 m drop.
  EXPECT_LT(summary.simulated[1].rms_height_error_m, 1e-3);
}

TEST(MeasuredTrajectory, NeedsTwoOnsets) {
  EXPECT_THROW(MeasuredTrajectory({1.0}, 0.2, 9.81, 1e-3), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
