#include "scatter_estimate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/random_stream.h"

namespace bouncecal::calibrate::internal {
namespace {

ImpactResiduals Residuals(std::vector<double> values, double timing_variance = 0) {
  ImpactResiduals result;
  result.residual =
      Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  result.timing_covariance =
      Eigen::MatrixXd::Identity(result.residual.size(), result.residual.size()) * timing_variance;
  return result;
}

TEST(ScatterEstimate, OneRecordingWithoutTimingNoiseGivesTheSampleVariance) {
  // Deviations 0.01, -0.02, 0.01 about their mean 0: sum of squares 6e-4 over 2 dof.
  const auto estimate = EstimateScatter({Residuals({0.01, -0.02, 0.01})}, 1);
  EXPECT_TRUE(estimate.within_estimable);
  EXPECT_EQ(estimate.within_dof, 2);
  EXPECT_NEAR(estimate.within_variance, 3e-4, 1e-15);
  EXPECT_EQ(estimate.between_dof, 0);
}

TEST(ScatterEstimate, TimingNoiseIsSubtractedAndTheRestTruncatedAtZero) {
  // Independent timing variance v per impact adds v to the expected sample variance.
  const auto with_timing = EstimateScatter({Residuals({0.01, -0.02, 0.01}, 1e-4)}, 1);
  EXPECT_NEAR(with_timing.within_variance, 2e-4, 1e-15);
  const auto timing_only = EstimateScatter({Residuals({0.01, -0.02, 0.01}, 1e-3)}, 1);
  EXPECT_EQ(timing_only.within_variance, 0.0);
  EXPECT_TRUE(timing_only.within_estimable);
}

TEST(ScatterEstimate, CorrelatedTimingCountsOnlyWhatReachesTheDeviations) {
  // Timing errors shared fully by all impacts (covariance v 11') move the mean, not the
  // deviations about it, so nothing is subtracted.
  auto shared = Residuals({0.01, -0.02, 0.01});
  shared.timing_covariance = Eigen::MatrixXd::Constant(3, 3, 1e-4);
  EXPECT_NEAR(EstimateScatter({shared}, 1).within_variance, 3e-4, 1e-15);
}

TEST(ScatterEstimate, ExtraFittedParametersCostDegreesOfFreedom) {
  const auto estimate = EstimateScatter({Residuals({0.01, -0.02, 0.01, 0.0})}, 2);
  EXPECT_EQ(estimate.within_dof, 2);  // 4 impacts - 1 mean - 1 extra parameter
  EXPECT_FALSE(EstimateScatter({Residuals({0.01, -0.01})}, 2).within_estimable);
}

TEST(ScatterEstimate, RecoversWithinAndBetweenVariancesOfSimulatedRecordings) {
  // 400 recordings of 5 impacts: eta_rk = b_r + eps_rk + timing, sd 0.01, 0.02, 0.005.
  RandomStream random(3, 0);
  std::vector<ImpactResiduals> recordings;
  for (int r = 0; r < 400; ++r) {
    const double offset = 0.01 * random.Gaussian();
    std::vector<double> values;
    for (int k = 0; k < 5; ++k)
      values.push_back(offset + 0.02 * random.Gaussian() + 0.005 * random.Gaussian());
    recordings.push_back(Residuals(values, 0.005 * 0.005));
  }
  const auto estimate = EstimateScatter(recordings, 1);
  EXPECT_EQ(estimate.within_dof, 1600);  // 400 x (5 - 1)
  EXPECT_EQ(estimate.between_dof, 399);
  // Relative standard errors: within sqrt(2/1600) * (1 + v/tau^2) = 4.4 %, between about
  // sqrt(2/399) * (tau_b^2 + tau_w^2/5 + v/5) / tau_b^2 = 13 %; checked to 3 of them.
  EXPECT_NEAR(estimate.within_variance, 4e-4, 0.13 * 4e-4);
  EXPECT_NEAR(estimate.between_variance, 1e-4, 0.4 * 1e-4);
}

TEST(ScatterEstimate, SingleImpactRecordingsLeaveTheScatterToTheBetweenPart) {
  const auto estimate =
      EstimateScatter({Residuals({0.03}), Residuals({-0.01}), Residuals({0.01})}, 1);
  EXPECT_FALSE(estimate.within_estimable);
  EXPECT_EQ(estimate.between_dof, 2);
  // Sample variance of 0.03, -0.01, 0.01: (0.02^2 + 0.02^2 + 0) / 2 = 4e-4.
  EXPECT_NEAR(estimate.between_variance, 4e-4, 1e-15);
}

}  // namespace
}  // namespace bouncecal::calibrate::internal
