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

// Deterministic standard normal draws: Box-Muller on a 64-bit LCG.
class NormalDraws {
 public:
  explicit NormalDraws(uint64_t seed) : state_(seed) {}
  double operator()() {
    return std::sqrt(-2 * std::log(Uniform())) * std::cos(2 * M_PI * Uniform());
  }

 private:
  double Uniform() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return ((state_ >> 11) + 0.5) / 9007199254740992.0;
  }
  uint64_t state_;
};

TEST(AnalyzeRestitution, PropagatedUncertaintyMatchesMonteCarloSpread) {
  // First-order propagation must agree with the spread of e under random onset jitter; 2000
  // draws give the sample sigma to about 3 %, so 10 % is a safe bound.
  const double sigma_t = 50e-6;
  const auto exact = GeometricSequence(0.2, 0.6, 9.81, 5, sigma_t);
  const auto analysed = AnalyzeRestitution(exact);
  NormalDraws normal(12345);
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

TEST(AnalyzeRestitution, AnIncomingFlightUncertaintyIsAShiftOfEveryEarlierOnset) {
  // A leading run on other sounds moves its onsets together: the flight after it changes, no
  // ratio inside it does. Shifts of onsets [0, 1) and [0, 4) by 1 ms and 0.5 ms, on top of 10 us
  // per onset, drawn 4000 times: the sample sigma is good to about 2 %, so 8 % is a safe bound.
  const double sigma_t = 10e-6;
  auto exact = GeometricSequence(0.2, 0.7, 9.81, 8, sigma_t);
  exact[1].incoming_flight_uncertainty_s = 1e-3;
  exact[4].incoming_flight_uncertainty_s = 0.5e-3;
  RestitutionOptions options;
  options.drop_height_m = 0.2;
  const auto analysed = AnalyzeRestitution(exact, options);
  EXPECT_NEAR(analysed.interval_uncertainty_s[3], std::hypot(sigma_t, sigma_t, 0.5e-3), 1e-12);
  EXPECT_NEAR(analysed.interval_uncertainty_s[2], std::hypot(sigma_t, sigma_t), 1e-12);

  NormalDraws normal(2024);
  const int draws = 4000;
  const size_t entries = analysed.energy_loss.size();
  std::vector<double> sum(entries + 1, 0.0), sum_sq(entries + 1, 0.0);
  for (int d = 0; d < draws; ++d) {
    auto jittered = exact;
    const double early_shift = 1e-3 * normal();
    const double run_shift = 0.5e-3 * normal();
    for (size_t i = 0; i < jittered.size(); ++i) {
      jittered[i].onset_s +=
          sigma_t * normal() + (i < 1 ? early_shift : 0.0) + (i < 4 ? run_shift : 0.0);
    }
    const auto drawn = AnalyzeRestitution(jittered, options);
    for (size_t j = 0; j <= entries; ++j) {
      const double value = j < entries ? drawn.energy_loss[j] : *drawn.energy_loss_mean_first_n;
      sum[j] += value;
      sum_sq[j] += value * value;
    }
  }
  for (size_t j = 0; j <= entries; ++j) {
    const double spread = std::sqrt(sum_sq[j] / draws - std::pow(sum[j] / draws, 2));
    const double stated = j < entries ? analysed.energy_loss_uncertainty[j]
                                      : *analysed.energy_loss_mean_first_n_uncertainty;
    EXPECT_NEAR(stated, spread, 0.08 * spread) << "energy loss entry " << j;
  }
  // eta_2's two flights lie inside the shifted runs: the onsets' 10 us alone.
  const auto onsets_only = AnalyzeRestitution(GeometricSequence(0.2, 0.7, 9.81, 8, sigma_t));
  EXPECT_NEAR(analysed.energy_loss_uncertainty[2], onsets_only.energy_loss_uncertainty[1], 1e-12);
}

TEST(AnalyzeRestitution, RejectsNonIncreasingOnsets) {
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {0.5, 0}}), ConfigError);
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {NAN, 0}}), ConfigError);
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {1.5, 0, -1e-3}}), ConfigError);
  EXPECT_THROW(AnalyzeRestitution({{1.0, 0}, {1.5, 0, NAN}}), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
