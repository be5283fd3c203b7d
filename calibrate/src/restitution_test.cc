#include "bouncecal/calibrate/restitution.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// Impact times of an ideal ball with constant restitution e dropped from h0: the flights form a
// geometric series dt_k = e^k dt_0.
std::vector<TimedImpact> GeometricSequence(double h0, double e, double g, int count,
                                           double sigma = 0) {
  std::vector<TimedImpact> impacts;
  double t = std::sqrt(2 * h0 / g);
  double flight = DropFlightTime(h0, g);
  for (int k = 0; k < count; ++k) {
    impacts.push_back({t, sigma});
    flight *= e;
    t += flight;
  }
  return impacts;
}

TEST(AnalyzeRestitution, PaperDropFlightTimeIs0404Seconds) {
  // docs/physics.md: dt_0 = 0.4040 s for h0 = 0.20 m, g = 9.8. The exact value is 0.404061 s; the
  // paper truncates to four decimals, so agreement is to 1e-4 s.
  EXPECT_NEAR(DropFlightTime(0.20, 9.8), 0.4040, 1e-4);
}

TEST(AnalyzeRestitution, GeometricSequenceGivesConstantRestitutionAndEnergyLoss) {
  const double e = 0.7;
  const auto impacts = GeometricSequence(0.2, e, 9.81, 6);
  RestitutionOptions options;
  options.drop_height_m = 0.2;
  const auto result = AnalyzeRestitution(impacts, options);
  ASSERT_EQ(result.restitution.size(), 5u);  // impacts 1..5 have an outgoing flight
  EXPECT_EQ(result.impact_index.front(), 0);
  for (size_t k = 0; k < result.restitution.size(); ++k) {
    EXPECT_NEAR(result.restitution[k], e, 1e-12);
    EXPECT_NEAR(result.energy_loss[k], 1 - e * e, 1e-12);
  }
  ASSERT_TRUE(result.energy_loss_mean_first_n.has_value());
  EXPECT_NEAR(*result.energy_loss_mean_first_n, 1 - e * e, 1e-12);
  // h_1 = e^2 h0 for a ballistic rebound.
  EXPECT_NEAR(result.bounce_height_m[0], e * e * 0.2, 1e-12);
}

TEST(AnalyzeRestitution, WithoutDropHeightFirstImpactHasNoRestitution) {
  const auto impacts = GeometricSequence(0.2, 0.8, 9.81, 4);
  const auto result = AnalyzeRestitution(impacts);
  ASSERT_EQ(result.restitution.size(), 2u);
  EXPECT_EQ(result.impact_index.front(), 1);
  EXPECT_FALSE(result.energy_loss_mean_first_n.has_value());  // 2 < first_n = 3
}

TEST(AnalyzeRestitution, PropagatedUncertaintyMatchesMonteCarloSpread) {
  // First-order propagation must agree with the spread of e under random onset jitter; 2000
  // draws give the sample sigma to about 3 %, so 10 % is a safe bound.
  const double sigma_t = 50e-6;
  const auto exact = GeometricSequence(0.2, 0.6, 9.81, 5, sigma_t);
  const auto analysed = AnalyzeRestitution(exact);
  uint64_t state = 12345;
  auto normal = [&state]() {
    // Box-Muller on a 64-bit LCG: deterministic and self-contained.
    auto uniform = [&state]() {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return ((state >> 11) + 0.5) / 9007199254740992.0;
    };
    return std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform());
  };
  double sum = 0, sum_sq = 0;
  const int draws = 2000;
  for (int d = 0; d < draws; ++d) {
    auto jittered = exact;
    for (auto& impact : jittered) impact.onset_s += sigma_t * normal();
    const double e = AnalyzeRestitution(jittered).restitution[1];
    sum += e;
    sum_sq += e * e;
  }
  const double spread = std::sqrt(sum_sq / draws - (sum / draws) * (sum / draws));
  EXPECT_NEAR(analysed.restitution_uncertainty[1], spread, 0.10 * spread);
}

TEST(AnalyzeRestitution, RejectsNonIncreasingOnsets) {
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {0.5, 0}}), ConfigError);
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {NAN, 0}}), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
