#include "bouncecal/export/drop_deck_check.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kG = 9.81;
constexpr double kRadius = 0.005;
constexpr double kContactS = 7.08e-5;

DropDeckRecord Record() {
  DropDeckRecord record;
  record.engine = "lammps";
  record.ball_radius_m = kRadius;
  record.gravity_mps2 = kG;
  record.time_step_s = 1.28e-7;
  record.expected_restitution = 0.5773502691896257;
  record.expected_contact_duration_s = kContactS;
  record.time_step_error_bound = 0.002;
  return record;
}

// Free flights sampled every 20 us around contacts of kContactS that keep `restitution`:
// exactly what an engine reproducing the law would write (the contact interior is never used).
std::vector<TrajectorySample> Trajectory(double restitution, int contacts) {
  std::vector<TrajectorySample> samples;
  double t0 = 0, z0 = kRadius + 0.2, v0 = 0;  // flight start
  for (int k = 0; k < contacts; ++k) {
    const double speed_in = std::sqrt(v0 * v0 + 2 * kG * (z0 - kRadius));
    const double touch = t0 + (v0 + speed_in) / kG;
    for (double t = std::ceil(t0 / 2e-5) * 2e-5; t < touch; t += 2e-5) {
      const double tau = t - t0;
      samples.push_back({t, z0 + v0 * tau - 0.5 * kG * tau * tau, v0 - kG * tau});
    }
    samples.push_back({touch + 0.5 * kContactS, kRadius - 1e-5, 0.0});
    t0 = touch + kContactS;
    z0 = kRadius;
    v0 = restitution * speed_in;
  }
  samples.push_back({t0 + 1e-3, z0 + v0 * 1e-3 - 0.5 * kG * 1e-6, v0 - kG * 1e-3});
  return samples;
}

TEST(CheckDropDeck, TrajectoryWithTheExpectedLawPasses) {
  const auto check = CheckDropDeck(Record(), Trajectory(0.5773502691896257, 6));
  ASSERT_EQ(check.bounces.size(), 6u);
  EXPECT_TRUE(check.passed);
  EXPECT_GE(check.judged, 4);
  // The synthetic trajectory is exact: deviations are rounding only.
  EXPECT_NEAR(check.bounces[0].restitution_deviation, 0.0, 1e-9);
  EXPECT_NEAR(check.bounces[0].duration_deviation, 0.0, 1e-6);
}

TEST(CheckDropDeck, RestitutionOffByThreePercentFails) {
  const auto check = CheckDropDeck(Record(), Trajectory(0.5773502691896257 * 1.03, 6));
  EXPECT_FALSE(check.passed);
  EXPECT_LT(check.within, check.judged);
}

TEST(CheckDropDeck, SlowBouncesAreReportedButNotJudged) {
  const auto check = CheckDropDeck(Record(), Trajectory(0.5773502691896257, 12));
  int unjudged = 0;
  for (const auto& bounce : check.bounces) {
    if (!bounce.judged) {
      ++unjudged;
      // g t_c / v > 1 % means an impact slower than 0.07 m/s.
      EXPECT_LT(bounce.bounce.impact_speed_mps, kG * kContactS / 0.01);
    }
  }
  EXPECT_GT(unjudged, 0);
}

TEST(CheckDropDeck, NoBouncesIsNotAPass) { EXPECT_FALSE(CheckDropDeck(Record(), {}).passed); }

TEST(CheckDropDeckFolder, MissingRecordIsAnInputError) {
  EXPECT_THROW(CheckDropDeckFolder("/nonexistent/deck"), InputError);
}

}  // namespace
}  // namespace bouncecal::calibrate
