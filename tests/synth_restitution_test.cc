// Synthesis and restitution analysis agree on the physics of a drop: the impact times the
// synthesiser plans give back the restitution law it was given (no detection involved; that
// round trip belongs to the detector's tests).
#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/calibrate/restitution.h"

namespace bouncecal::testing {
namespace {

std::vector<calibrate::TimedImpact> Timed(const std::vector<double>& onsets) {
  std::vector<calibrate::TimedImpact> impacts;
  for (double onset : onsets) impacts.push_back({onset, 0.0});
  return impacts;
}

TEST(SynthRestitution, PapersDropGivesBackEtaBarOf058) {
  const audio::SynthesisOptions options;  // defaults: the paper's drop
  const auto recording = audio::SynthesizeBounces(options);
  calibrate::RestitutionOptions analysis;
  analysis.drop_height_m = options.drop.drop_height_m;
  analysis.gravity_mps2 = options.gravity_mps2;
  const auto result = calibrate::AnalyzeRestitution(Timed(recording.BallImpactOnsetsS()), analysis);
  ASSERT_GE(result.energy_loss.size(), 5u);
  // Exact ballistic times: eta_k = 1 - e^2 = 0.58 for every impact, to rounding.
  for (double eta : result.energy_loss) EXPECT_NEAR(eta, 0.58, 1e-9);
  ASSERT_TRUE(result.energy_loss_mean_first_n.has_value());
  EXPECT_NEAR(*result.energy_loss_mean_first_n, 0.58, 1e-9);
}

TEST(SynthRestitution, SpeedDependentLawIsRecoveredImpactByImpact) {
  audio::SynthesisOptions options;
  options.drop.drop_height_m = 0.5;
  options.drop.restitution.constant = 0.9;
  options.drop.restitution.slope_per_mps = -0.05;
  const auto plan = audio::PlanBallImpacts(options);
  std::vector<double> onsets;
  for (const auto& impact : plan) onsets.push_back(impact.onset_s);
  calibrate::RestitutionOptions analysis;
  analysis.drop_height_m = 0.5;
  const auto result = calibrate::AnalyzeRestitution(Timed(onsets), analysis);
  ASSERT_EQ(result.restitution.size(), plan.size() - 1);
  for (size_t j = 0; j < result.restitution.size(); ++j) {
    const double v = plan[static_cast<size_t>(result.impact_index[j])].impact_speed_mps;
    EXPECT_NEAR(result.restitution[j], 0.9 - 0.05 * v, 1e-9) << "impact " << j;
  }
}

}  // namespace
}  // namespace bouncecal::testing
