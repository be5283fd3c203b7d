#include "sandwich.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bouncecal::calibrate::internal {
namespace {

// The simplest estimator there is: x fitted to n data y_i = t_i (the onsets themselves) with
// weights w_i, i.e. the weighted mean of the onsets; each datum has its own jitter term.
SequenceLinearization WeightedMean(const Eigen::VectorXd& weights,
                                   const Eigen::VectorXd& onset_variance) {
  const Eigen::Index n = weights.size();
  SequenceLinearization linear;
  linear.parameters = Eigen::MatrixXd::Ones(n, 1);  // model x for every datum
  linear.weights = weights;
  linear.residual = Eigen::VectorXd::Zero(n);
  linear.onsets = -Eigen::MatrixXd::Identity(n, n);  // r = x - t
  linear.onset_variance = onset_variance;
  linear.jitter = Eigen::MatrixXd::Identity(n, n);
  return linear;
}

TEST(Sandwich, WeightedMeanHasTheTextbookVariance) {
  // Var(sum w t / sum w) = sum w^2 var / (sum w)^2.
  Eigen::VectorXd w(3), v(3);
  w << 1, 2, 4;
  v << 0.5, 0.25, 2;
  const auto parts = SandwichCovariance({WeightedMean(w, v)});
  ASSERT_TRUE(parts.ok);
  const double expected = (1 * 0.5 + 4 * 0.25 + 16 * 2) / 49.0;
  EXPECT_NEAR(parts.timing(0, 0), expected, 1e-14);
  // Unit per-datum jitter: sum w^2 / (sum w)^2.
  EXPECT_NEAR(parts.within(0, 0), 21.0 / 49.0, 1e-14);
  // A unit offset of every datum moves the weighted mean by exactly 1.
  EXPECT_NEAR(parts.between(0, 0), 1.0, 1e-14);
}

TEST(Sandwich, IndependentSequencesAddTheirInformation) {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(4), v = Eigen::VectorXd::Ones(4);
  const auto one = SandwichCovariance({WeightedMean(w, v)});
  const auto two = SandwichCovariance({WeightedMean(w, v), WeightedMean(w, v)});
  EXPECT_NEAR(two.timing(0, 0), one.timing(0, 0) / 2, 1e-14);
  // Two sequences' offsets are independent: the mean of two has half the offset variance.
  EXPECT_NEAR(two.between(0, 0), 0.5, 1e-14);
}

TEST(Sandwich, SharedDropHeightDoesNotAverageOut) {
  auto a = WeightedMean(Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(2));
  a.drop_height = Eigen::VectorXd::Constant(2, -3.0);  // r = x - 3 h: x moves by 3 per unit h
  const auto parts = SandwichCovariance({a, a});
  EXPECT_NEAR(parts.drop_height(0, 0), 9.0, 1e-12);
}

TEST(Sandwich, UndeterminedParametersAreRefused) {
  auto linear = WeightedMean(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(3));
  linear.parameters = Eigen::MatrixXd::Ones(3, 2);  // two parameters with the same effect
  EXPECT_FALSE(SandwichCovariance({linear}).ok);
  EXPECT_EQ(SingleSequenceStep(linear).size(), 0);
}

TEST(Sandwich, SingleSequenceStepSolvesALinearFit) {
  // Residuals r = x - t at x = 0 with t = (1, 2, 3): the step to the mean is +2.
  auto linear = WeightedMean(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(3));
  linear.residual << -1, -2, -3;
  const auto step = SingleSequenceStep(linear);
  ASSERT_EQ(step.size(), 1);
  EXPECT_NEAR(step[0], 2.0, 1e-14);
}

}  // namespace
}  // namespace bouncecal::calibrate::internal
