#include "model_adequacy.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/random_stream.h"

namespace bouncecal::calibrate::internal {
namespace {

// Impacts at speeds 2.0, 1.8, ... m/s with residual slope * ln(speed) + scatter * z.
std::vector<AdequacyImpact> Impacts(double slope, double scatter, int count, std::uint64_t seed,
                                    int sequence = 0) {
  RandomStream random(seed, static_cast<std::uint64_t>(sequence));
  std::vector<AdequacyImpact> impacts;
  for (int k = 0; k < count; ++k) {
    const double speed = 2.0 - 0.2 * k;
    impacts.push_back(
        {sequence, speed, slope * std::log(speed) + scatter * random.Gaussian(), 1e-8});
  }
  return impacts;
}

AdequacyContext WaltonBraun() { return {"walton-braun", false, false}; }

TEST(ModelAdequacy, ATrendFarBeyondTheScatterIsFlaggedWithTheNextStep) {
  const auto result = TestSpeedTrend(Impacts(0.05, 0.005, 10, 1), WaltonBraun());
  ASSERT_TRUE(result.tested);
  EXPECT_TRUE(result.trend);
  // ln(speed) of 0.2..2.0 m/s spreads by sd 0.66, scatter 0.005: the slope's standard error is
  // about 0.005 / (0.66 sqrt(10)); checked to 4 of them.
  EXPECT_NEAR(result.slope_per_ln_speed, 0.05, 4 * 0.005 / (0.66 * std::sqrt(10.0)));
  EXPECT_NEAR(result.change_over_range, result.slope_per_ln_speed * std::log(10.0), 1e-12);
  EXPECT_NEAR(result.speed_min_mps, 0.2, 1e-12);
  EXPECT_NEAR(result.speed_max_mps, 2.0, 1e-12);
  EXPECT_NE(result.message.find("one constant gamma_n does not describe"), std::string::npos)
      << result.message;
  EXPECT_NE(result.message.find("`compare_laws`"), std::string::npos) << result.message;
}

TEST(ModelAdequacy, PureScatterRaisesNoAlarmInNearlyAllSeeds) {
  // At the 99 % level about 1 in 100 seeds flags a trend that is not there.
  int alarms = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed)
    alarms += TestSpeedTrend(Impacts(0, 0.02, 8, seed), WaltonBraun()).trend ? 1 : 0;
  // Binomial(200, 0.01): mean 2, P(more than 8) < 1e-3.
  EXPECT_LE(alarms, 8);
  const auto quiet = TestSpeedTrend(Impacts(0, 0.02, 8, 0), WaltonBraun());
  EXPECT_NE(quiet.message.find("no trend"), std::string::npos) << quiet.message;
}

TEST(ModelAdequacy, EachRecordingKeepsItsOwnOffset) {
  // Two recordings with the same slope-free scatter but offsets 0 and 0.1: pooled without
  // intercepts, the offset would look like a trend if their speeds differed.
  auto impacts = Impacts(0, 0.002, 6, 4, 0);
  for (auto impact : Impacts(0, 0.002, 6, 5, 1)) {
    impact.speed_mps += 3;
    impact.residual += 0.1;
    impacts.push_back(impact);
  }
  EXPECT_FALSE(TestSpeedTrend(impacts, WaltonBraun()).trend);
}

// A drop whose simulated contact is shorter than the ball's shifts eta_k in the pattern of the
// contact's duration (its onset intervals hold the contact, and gravity acts during it): with the
// sensitivity known, that pattern is the stiffness's, not a trend of the damping, while a trend
// in ln(speed) is still found. The pattern here is the contact-in-interval one, growing as
// 1 / speed^2 as flights shorten (each interval's share of contact).
TEST(ModelAdequacy, AContactDurationPatternIsNotATrendButATrendStillIs) {
  // Speeds 2.0 to 0.4 m/s, scatter and timing sd 2e-5 each; the pattern reaches 9e-4.
  const auto with_pattern = [](double slope) {
    auto impacts = Impacts(slope, 2e-5, 9, 7);
    for (auto& impact : impacts) {
      impact.timing_variance = 4e-10;
      impact.contact_sensitivity = -1e-4 / (impact.speed_mps * impact.speed_mps);
      impact.residual += 1.5 * impact.contact_sensitivity;
    }
    return impacts;
  };
  auto unknown = with_pattern(0);
  for (auto& impact : unknown) impact.contact_sensitivity = 0;
  EXPECT_TRUE(TestSpeedTrend(unknown, WaltonBraun()).trend);
  EXPECT_FALSE(TestSpeedTrend(with_pattern(0), WaltonBraun()).trend);
  // A change of 0.0016 in eta over the speeds, beside the pattern's 0.0009.
  EXPECT_TRUE(TestSpeedTrend(with_pattern(0.001), WaltonBraun()).trend);
}

TEST(ModelAdequacy, TooFewImpactsAreNotTested) {
  const auto result = TestSpeedTrend(Impacts(0.05, 0.001, 3, 1), WaltonBraun());
  EXPECT_FALSE(result.tested);
  EXPECT_FALSE(result.trend);
  EXPECT_NE(result.message.find("not tested"), std::string::npos);
}

TEST(ModelAdequacy, MessagesNameTheLawAndDoNotSendAComparisonBackToItself) {
  const auto impacts = Impacts(0.05, 0.005, 10, 1);
  const auto hertz = TestSpeedTrend(impacts, {"hertz-viscoelastic", true, false});
  EXPECT_NE(hertz.message.find("speed dependence of hertz-viscoelastic"), std::string::npos)
      << hertz.message;
  const auto compared = TestSpeedTrend(impacts, {"hertz-viscoelastic", true, true});
  EXPECT_EQ(compared.message.find("`compare_laws`"), std::string::npos) << compared.message;
  EXPECT_NE(compared.message.find("`first_n`"), std::string::npos) << compared.message;
}

}  // namespace
}  // namespace bouncecal::calibrate::internal
