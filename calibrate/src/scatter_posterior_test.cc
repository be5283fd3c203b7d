#include "scatter_posterior.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/random_stream.h"
#include "student_t.h"

namespace bouncecal::calibrate::internal {
namespace {

// `count` impacts at speeds 2.0, 1.8, ... m/s: residual slope ln(speed) + tau z + timing, the
// stated timing sd of impact k `timing_sd[k]` (the last entry repeats).
std::vector<AdequacyImpact> Impacts(double slope, double tau, const std::vector<double>& timing_sd,
                                    int count, std::uint64_t seed, int sequence = 0) {
  RandomStream random(seed, static_cast<std::uint64_t>(sequence));
  std::vector<AdequacyImpact> impacts;
  for (int k = 0; k < count; ++k) {
    const double speed = 2.0 * std::pow(0.8, k);
    const double sd = timing_sd[std::min<size_t>(static_cast<size_t>(k), timing_sd.size() - 1)];
    impacts.push_back({sequence, speed,
                       slope * std::log(speed) + tau * random.Gaussian() + sd * random.Gaussian(),
                       sd * sd});
  }
  return impacts;
}

// With timing far below the scatter the Jeffreys prior is 1/tau, under which the slope's
// posterior is Student's t with impacts - 2 dof about the least-squares slope, scaled by its
// usual standard error: the posterior tail must be the t test's one-sided p-value. The grid and
// the timing variance (1e-4 of tau^2) leave differences of a few 1e-4.
TEST(ScatterPosterior, SlopeTailIsTheClassicalTTestWhenTimingIsNegligible) {
  const auto impacts = Impacts(0.004, 0.01, {1e-4}, 8, 7);
  const auto posterior = FitScatterPosterior(impacts, /*with_slope=*/true);
  ASSERT_TRUE(posterior.ok);
  EXPECT_EQ(posterior.dof, 6);
  double sx = 0, sy = 0;
  for (const auto& impact : impacts) {
    sx += std::log(impact.speed_mps) / 8;
    sy += impact.residual / 8;
  }
  double sxx = 0, sxy = 0;
  for (const auto& impact : impacts) {
    sxx += std::pow(std::log(impact.speed_mps) - sx, 2);
    sxy += (std::log(impact.speed_mps) - sx) * (impact.residual - sy);
  }
  const double slope = sxy / sxx;
  double squares = 0;
  for (const auto& impact : impacts)
    squares += std::pow(impact.residual - sy - slope * (std::log(impact.speed_mps) - sx), 2);
  const double se = std::sqrt(squares / 6 / sxx);
  EXPECT_NEAR(posterior.SlopeAboveZero(), StudentTCdf(slope / se, 6), 2e-3);
}

// The mechanism of issue 29: a few precise impacts (25 us onsets) and many imprecise ones (ms),
// constant energy loss with scatter 0.01. A test whose variance estimate can sit near zero by
// chance (and whose degrees of freedom count the imprecise impacts) claims trends far more often
// than its level: the Paule-Mandel t test this replaced claimed 118 of these 2000. Integrating
// over tau's posterior keeps the 1 % level (measured: 20). Binomial(2000, 0.01) exceeds 32 with
// probability 8e-4.
TEST(ScatterPosterior, TrendTestKeepsItsLevelWhenFewImpactsArePrecise) {
  const std::vector<double> timing = {2e-4, 3e-4, 5e-4, 1e-3, 0.02, 0.05, 0.1, 0.2};
  int alarms = 0;
  for (std::uint64_t seed = 0; seed < 2000; ++seed) {
    const auto posterior = FitScatterPosterior(Impacts(0, 0.01, timing, 9, seed), true);
    ASSERT_TRUE(posterior.ok);
    alarms += posterior.SlopeExcludesZero(0.99) ? 1 : 0;
  }
  RecordProperty("alarms", alarms);
  EXPECT_LE(alarms, 32);
  // And not by never claiming anything: a slope of 0.1 per ln(speed), a change of 0.067 over the
  // four precise impacts against a scatter of 0.01, is found in 172 of 200 seeds.
  int found = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed)
    found += FitScatterPosterior(Impacts(0.1, 0.01, timing, 9, seed), true).SlopeExcludesZero(0.99)
                 ? 1
                 : 0;
  EXPECT_GE(found, 150);
}

TEST(ScatterPosterior, MedianTauRecoversTheScatterOfManyImpacts) {
  // 40 sequences of 10 impacts, tau 0.02, timing 0.005: tau's relative sd is about
  // 1 / sqrt(2 * 360) = 4 %; checked to 3 of them.
  std::vector<AdequacyImpact> impacts;
  for (int r = 0; r < 40; ++r) {
    for (auto impact : Impacts(0, 0.02, {0.005}, 10, 11, r)) {
      impact.residual += 0.1 * r;  // each sequence keeps its own intercept
      impacts.push_back(impact);
    }
  }
  const auto posterior = FitScatterPosterior(impacts, /*with_slope=*/false);
  ASSERT_TRUE(posterior.ok);
  EXPECT_EQ(posterior.dof, 360);
  EXPECT_NEAR(posterior.TauQuantile(0.5), 0.02, 0.12 * 0.02);
  EXPECT_LT(posterior.TauQuantile(0.05), posterior.TauQuantile(0.95));
}

TEST(ScatterPosterior, NoScatterLeavesTauBelowTheTiming) {
  // Timing alone (sd 0.001): tau's posterior sits below it, so an interval stays near the
  // timing-only width.
  const auto posterior = FitScatterPosterior(Impacts(0, 0, {0.001}, 30, 3), false);
  ASSERT_TRUE(posterior.ok);
  EXPECT_LT(posterior.TauQuantile(0.5), 0.001);
  EXPECT_LT(posterior.TauQuantile(0.95), 0.0015);
}

// Impacts whose timing noise is `actual` times the stated sd: three precise (0.5e-3) then
// imprecise ones (4e-3), as a detector states band onsets and residual-only ones.
std::vector<AdequacyImpact> MisstatedTiming(double actual, int count, std::uint64_t seed) {
  RandomStream random(seed, 0);
  std::vector<AdequacyImpact> impacts;
  for (int k = 0; k < count; ++k) {
    const double sd = k < 3 ? 0.5e-3 : 4e-3;
    impacts.push_back({0, 2.0 * std::pow(0.8, k), actual * sd * random.Gaussian(), sd * sd});
  }
  return impacts;
}

// The stated sds four times the noise (the chain-coverage bench's drops without scatter show
// 0.27-0.28): the timing scale's posterior median follows the residuals. From 30 impacts phi's
// relative sd is about 1/sqrt(2 * 30) = 0.13, so [0.17, 0.36] is +-2.9 sd about 0.25 and
// [0.7, 1.4] about 1 when the sds are right. The imprecise impacts' noise (1e-3) is not read as
// scatter: tau's median stays below half of it. (Three precise impacts cannot exclude a tau as
// large as their own noise, 1.25e-4: its median is 1.6e-4 here, the interval's remaining excess
// without scatter.)
TEST(ScatterPosterior, TheTimingScaleFollowsTheResidualsWhenTheStatedSigmasAreTooLarge) {
  const auto scaled = FitScatterPosterior(MisstatedTiming(0.25, 30, 5), false, true);
  ASSERT_TRUE(scaled.ok);
  EXPECT_TRUE(scaled.timing_scaled);
  EXPECT_GT(scaled.TimingScaleQuantile(0.5), 0.17);
  EXPECT_LT(scaled.TimingScaleQuantile(0.5), 0.36);
  EXPECT_LT(scaled.TauQuantile(0.5), 0.5 * 0.25 * 4e-3);
  const auto right = FitScatterPosterior(MisstatedTiming(1.0, 30, 5), false, true);
  ASSERT_TRUE(right.ok);
  EXPECT_GT(right.TimingScaleQuantile(0.5), 0.7);
  EXPECT_LT(right.TimingScaleQuantile(0.5), 1.4);
  // Without it every node takes the stated sds.
  const auto stated = FitScatterPosterior(MisstatedTiming(0.25, 30, 5), false);
  EXPECT_FALSE(stated.timing_scaled);
  EXPECT_DOUBLE_EQ(stated.TimingScaleQuantile(0.05), 1.0);
  EXPECT_DOUBLE_EQ(stated.TimingScaleQuantile(0.95), 1.0);
}

// With real scatter (tau = 0.02, timing sds 0.5e-3 and 4e-3) the timing scale cannot take the
// scatter's place: tau's median is still within 15 % of 0.02 (40 impacts: tau's relative sd
// about 1/sqrt(2 * 40) = 0.11; the scale adds little where scatter dominates).
TEST(ScatterPosterior, TheTimingScaleLeavesTheScatterToTau) {
  auto impacts = MisstatedTiming(1.0, 40, 9);
  RandomStream random(9, 1);
  for (auto& impact : impacts) impact.residual += 0.02 * random.Gaussian();
  const auto posterior = FitScatterPosterior(impacts, false, true);
  ASSERT_TRUE(posterior.ok);
  EXPECT_NEAR(posterior.TauQuantile(0.5), 0.02, 0.15 * 0.02);
}

TEST(ScatterPosterior, TooFewImpactsOrOneSpeedIsNotOk) {
  EXPECT_FALSE(FitScatterPosterior(Impacts(0, 0.01, {1e-3}, 2, 1), true).ok);
  auto same_speed = Impacts(0, 0.01, {1e-3}, 5, 1);
  for (auto& impact : same_speed) impact.speed_mps = 1;
  EXPECT_FALSE(FitScatterPosterior(same_speed, true).ok);
  EXPECT_TRUE(FitScatterPosterior(same_speed, false).ok);
}

}  // namespace
}  // namespace bouncecal::calibrate::internal
