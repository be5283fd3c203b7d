#include "bouncecal/export/trajectory_bounces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kG = 9.81;
constexpr double kRadius = 0.005;

struct SyntheticDrop {
  std::vector<TrajectorySample> samples;
  std::vector<double> contact_starts_s, contact_ends_s, impact_speeds_mps;
};

// An exact piecewise trajectory: drag-free flights between contacts of duration contact_s, each
// rebounding with `restitution`. Inside a contact the centre dips below the touching height and vz
// turns linearly from down to up (the analyser must not rely on what happens in there). Sampled
// every interval_s from the release at height drop_m (lowest point above the wall).
SyntheticDrop MakeDrop(double drop_m, double restitution, double contact_s, double interval_s,
                       int contacts) {
  SyntheticDrop drop;
  struct Phase {
    double start_s, z0_m, vz0_mps;  // a flight from (z0, vz0)...
    double contact_start_s, contact_end_s, speed_in, speed_out;
  };
  std::vector<Phase> phases;
  double t = 0, z0 = kRadius + drop_m, vz0 = 0;
  for (int k = 0; k < contacts; ++k) {
    const double speed_in = std::sqrt(vz0 * vz0 + 2 * kG * (z0 - kRadius));
    const double touch = t + (vz0 + speed_in) / kG;
    const double speed_out = restitution * speed_in;
    phases.push_back({t, z0, vz0, touch, touch + contact_s, speed_in, speed_out});
    drop.contact_starts_s.push_back(touch);
    drop.contact_ends_s.push_back(touch + contact_s);
    drop.impact_speeds_mps.push_back(speed_in);
    t = touch + contact_s;
    z0 = kRadius;
    vz0 = speed_out;
  }
  const double end_s = phases.back().contact_start_s;  // stop at the last touch
  for (double time = 0; time < end_s; time += interval_s) {
    size_t p = 0;
    while (p + 1 < phases.size() && time >= phases[p + 1].start_s) ++p;
    const Phase& phase = phases[p];
    TrajectorySample s{time, 0, 0};
    if (time < phase.contact_start_s) {
      const double tau = time - phase.start_s;
      s.z_m = phase.z0_m + phase.vz0_mps * tau - 0.5 * kG * tau * tau;
      s.vz_mps = phase.vz0_mps - kG * tau;
    } else {
      const double u =
          (time - phase.contact_start_s) / (phase.contact_end_s - phase.contact_start_s);
      s.z_m = kRadius - 1e-5 * std::sin(std::numbers::pi * u);
      s.vz_mps = -phase.speed_in + u * (phase.speed_in + phase.speed_out);
    }
    drop.samples.push_back(s);
  }
  return drop;
}

TEST(FindTrajectoryBounces, RecoversRestitutionSpeedsAndContactTimesOfAnExactTrajectory) {
  const auto drop = MakeDrop(0.2, 0.6, 7e-5, 3e-5, 6);
  const auto found = FindTrajectoryBounces(drop.samples, {kRadius, 0, kG});
  // The last touch has no rebound in the samples; the trajectory ends in flight before it.
  ASSERT_EQ(found.bounces.size(), 5u);
  EXPECT_EQ(found.unresolved_contacts, 0);
  for (size_t k = 0; k < found.bounces.size(); ++k) {
    // Ballistic extrapolation is exact; only rounding (1e-16 relative, amplified by the
    // subtraction z - z_touch of centimetre heights) remains, so 1e-9 is a generous bound.
    EXPECT_NEAR(found.bounces[k].restitution, 0.6, 1e-9) << k;
    EXPECT_NEAR(found.bounces[k].impact_speed_mps, drop.impact_speeds_mps[k], 1e-9) << k;
    EXPECT_NEAR(found.bounces[k].contact_start_s, drop.contact_starts_s[k], 1e-9) << k;
    EXPECT_NEAR(found.bounces[k].contact_end_s, drop.contact_ends_s[k], 1e-9) << k;
  }
}

TEST(FindTrajectoryBounces, ABallRestingOnTheWallEndsInContact) {
  auto drop = MakeDrop(0.05, 0.5, 7e-5, 2e-5, 3);
  const double last = drop.samples.back().time_s;
  for (int i = 1; i <= 10; ++i) drop.samples.push_back({last + i * 1e-3, kRadius - 4e-9, 0.0});
  const auto found = FindTrajectoryBounces(drop.samples, {kRadius, 0, kG});
  EXPECT_TRUE(found.ends_in_contact);
  EXPECT_EQ(found.bounces.size(), 2u);
}

TEST(FindTrajectoryBounces, ContactWithoutAReversalIsCountedAsUnresolved) {
  // Sampled so coarsely that the samples around the dip both move downward: no rebound seen.
  std::vector<TrajectorySample> samples = {
      {0.0, 0.01, -1.0}, {0.001, 0.004, -1.0}, {0.002, 0.006, -0.5}, {0.003, 0.007, 0.5}};
  const auto found = FindTrajectoryBounces(samples, {kRadius, 0, kG});
  EXPECT_TRUE(found.bounces.empty());
  EXPECT_EQ(found.unresolved_contacts, 1);
}

TEST(FindTrajectoryBounces, NonPositiveRadiusOrGravityIsAConfigError) {
  EXPECT_THROW(FindTrajectoryBounces({}, {0.0, 0, kG}), ConfigError);
  EXPECT_THROW(FindTrajectoryBounces({}, {kRadius, 0, -9.81}), ConfigError);
}

TEST(ParseTrajectory, SkipsCommentsAndReadsThreeColumns) {
  const auto samples = ParseTrajectory("# time_s z_m vz_mps\n\n0 0.205 0\n1e-05 0.2049 -9.8e-05\n",
                                       "trajectory.txt");
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[1].time_s, 1e-5);
  EXPECT_DOUBLE_EQ(samples[1].z_m, 0.2049);
  EXPECT_DOUBLE_EQ(samples[1].vz_mps, -9.8e-5);
}

TEST(ParseTrajectory, MalformedLineNamesTheFileAndLine) {
  try {
    ParseTrajectory("# header\n0 0.2 0\n1e-5 0.2 oops\n", "deck/trajectory.txt");
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("deck/trajectory.txt:3"), std::string::npos)
        << error.what();
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << "one line";
  }
  EXPECT_THROW(ParseTrajectory("0 0.2 0 7\n", "t.txt"), InputError);
}

TEST(ParseTrajectory, TimeThatDoesNotIncreaseIsAnInputError) {
  EXPECT_THROW(ParseTrajectory("0 0.2 0\n0 0.2 0\n", "t.txt"), InputError);
}

TEST(ReadTrajectory, MissingFileIsAnInputError) {
  EXPECT_THROW(ReadTrajectory("/nonexistent/trajectory.txt"), InputError);
}

}  // namespace
}  // namespace bouncecal::calibrate
