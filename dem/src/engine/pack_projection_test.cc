#include "bouncecal/dem/pack_projection.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bouncecal::dem {
namespace {

// The prior is work over speed: twice the particles or twice the steps at the same speed take
// twice as long (exact up to rounding: 1e-12 relative).
TEST(PackProjection, PriorScalesWithParticlesTimesSteps) {
  const double base = ProjectWallTimeS(2000, 300000, 1);
  EXPECT_GT(base, 0);
  EXPECT_NEAR(ProjectWallTimeS(2000, 600000, 1), 2 * base, 1e-12 * base);
  // Between table rows the speed changes, so twice the particles cost at least not less than
  // twice (the speed per particle-step never rises with size).
  EXPECT_GE(ProjectWallTimeS(4000, 300000, 1), 2 * base * (1 - 1e-12));
  EXPECT_LT(ProjectWallTimeS(2000, 300000, 2), base);      // a second thread helps
  EXPECT_GT(ProjectWallTimeS(2000, 300000, 2), base / 2);  // but less than twice
}

// The reference speed is interpolated between rows and never extrapolated upwards: monotone
// non-increasing with size, finite for one particle and for 10^8.
TEST(PackProjection, ReferenceSpeedIsMonotoneAndFinite) {
  double previous = ReferenceParticleStepsPerS(1, 1);
  for (double n = 1; n <= 1e8; n *= 1.5) {
    const double rate = ReferenceParticleStepsPerS(static_cast<std::int64_t>(n), 1);
    EXPECT_TRUE(std::isfinite(rate));
    EXPECT_GT(rate, 0);
    EXPECT_LE(rate, previous * (1 + 1e-12)) << n;
    previous = rate;
  }
}

// A run at a steady speed R: once measured, the projection is exactly the remaining
// particle-steps over R, whatever the prior said (the prior here is off by the host's speed).
TEST(PackProjection, SteadyRunProjectsItsOwnSpeed) {
  const std::int64_t particles = 1000;
  const std::int64_t total = 100000;
  const double rate = 1e6;  // particle-steps per second, far from the reference host's
  WallTimeProjection projection(particles, total, 1);
  EXPECT_NEAR(projection.Update(0, particles, 0), projection.prior_s(), 1e-9);
  for (std::int64_t step = 2000; step <= total; step += 2000) {
    const double wall = static_cast<double>(particles * step) / rate;
    const double expected = static_cast<double>(particles * (total - step)) / rate;
    EXPECT_NEAR(projection.Update(step, particles, wall), expected, 1e-9 * (1 + expected)) << step;
  }
}

// A pour: the scene fills up, so the remaining steps are charged at the final count, not the
// current one; with a per-particle cost that does not change, the projection is exact from the
// first measured stretch on even though only a tenth of the particles are in.
TEST(PackProjection, PourIsChargedAtTheFinalCount) {
  const std::int64_t final_count = 10000;
  const std::int64_t total = 50000;
  const double rate = 4e6;
  WallTimeProjection projection(final_count, total, 2);
  double wall = 0;
  for (std::int64_t step = 1000; step <= total; step += 1000) {
    const std::int64_t now = std::min<std::int64_t>(final_count, final_count * step / 10000 + 1);
    wall += static_cast<double>(now * 1000) / rate;
    const double expected = static_cast<double>(final_count * (total - step)) / rate;
    EXPECT_NEAR(projection.Update(step, now, wall), expected, 1e-9 * (1 + expected)) << step;
  }
}

// When the run slows down (the host got loaded, the pack settled), the projection follows within
// a few smoothing times: after 60 s of wall at the new speed it is within 1 % of the new figure.
TEST(PackProjection, FollowsASlowdown) {
  const std::int64_t particles = 2000;
  const std::int64_t total = 10000000;
  WallTimeProjection projection(particles, total, 1);
  double wall = 0;
  std::int64_t step = 0;
  auto run = [&](double rate, double seconds) {
    double remaining = 0;
    for (double t = 0; t < seconds; t += 1.0) {
      const auto steps = static_cast<std::int64_t>(rate / particles);
      step += steps;
      wall += static_cast<double>(steps * particles) / rate;
      remaining = projection.Update(step, particles, wall);
    }
    return remaining;
  };
  run(4e7, 20);
  const double slow = 1e7;
  const double remaining = run(slow, 60);
  const double expected = static_cast<double>((total - step) * particles) / slow;
  EXPECT_NEAR(remaining, expected, 0.01 * expected);
}

// A resumed run starts measuring from its checkpoint: the steps before it took no wall time of
// this run and must not read as infinitely fast.
TEST(PackProjection, ResumedRunMeasuresFromItsFirstStep) {
  const std::int64_t particles = 500;
  const double rate = 2e6;
  WallTimeProjection projection(particles, 200000, 1, 150000, 0.5);
  const double wall = 0.5 + static_cast<double>(particles * 10000) / rate;
  const double expected = static_cast<double>(particles * 40000) / rate;
  EXPECT_NEAR(projection.Update(160000, particles, wall), expected, 1e-9 * expected);
  EXPECT_NEAR(projection.prior_s(), ProjectWallTimeS(particles, 50000, 1), 1e-12);
}

}  // namespace
}  // namespace bouncecal::dem
