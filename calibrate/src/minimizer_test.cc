#include "bouncecal/calibrate/minimizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

TEST(BoundedMinimizer, DefaultOptionsAreValid) {
  EXPECT_NO_THROW(BoundedMinimizer({0.0}, {1.0}, MinimizerOptions{}));
}

TEST(BoundedMinimizer, FindsTheMinimumOfAQuadraticInOneDimension) {
  const BoundedMinimizer minimizer({0.0}, {1.0});
  const auto summary = minimizer.Minimize(
      [](std::span<const double> x) { return std::pow(x[0] - 0.408, 2); }, {0.5});
  // parameter_tolerance 1e-5 of a unit box: BOBYQA stops within a few tolerances of the optimum.
  EXPECT_NEAR(summary.x[0], 0.408, 1e-4);
  EXPECT_TRUE(IsConverged(summary.stop)) << summary.message;
  EXPECT_GT(summary.evaluations, 0);
  EXPECT_LE(summary.evaluations, MinimizerOptions{}.max_evaluations);
}

TEST(BoundedMinimizer, RespectsBoundsWhenTheMinimumLiesOutside) {
  const BoundedMinimizer minimizer({0.0, 0.0}, {1.0, 1.0});
  const auto summary = minimizer.Minimize(
      [](std::span<const double> x) { return std::pow(x[0] - 2.0, 2) + std::pow(x[1] - 0.3, 2); },
      {0.5, 0.5});
  // The constrained optimum is (1, 0.3) exactly; tolerance as above.
  EXPECT_NEAR(summary.x[0], 1.0, 1e-4);
  EXPECT_NEAR(summary.x[1], 0.3, 1e-4);
}

TEST(BoundedMinimizer, EveryLocalMethodSolvesAnIllConditionedBoundedQuadratic) {
  // A rotated ellipsoid with condition number 100 centred at (0.6, 1.2): the shape of a
  // two-parameter calibration objective whose parameters trade off against each other.
  auto objective = [](std::span<const double> x) {
    const double u = (x[0] - 0.6) + (x[1] - 1.2), v = (x[0] - 0.6) - (x[1] - 1.2);
    return 100 * u * u + v * v;
  };
  for (auto method : {LocalMethod::kBobyqa, LocalMethod::kCobyla, LocalMethod::kNelderMead}) {
    MinimizerOptions options;
    options.local_method = method;
    options.max_evaluations = 2000;
    options.parameter_tolerance = 1e-8;
    const BoundedMinimizer minimizer({-2.0, -1.0}, {2.0, 3.0}, options);
    const auto summary = minimizer.Minimize(objective, {-1.2, 1.0});
    // xtol 1e-8 of a 4-wide box; 1e-4 leaves room for the simplex methods' slower last steps
    // along the flat direction (curvature 1) of the valley.
    EXPECT_NEAR(summary.x[0], 0.6, 1e-4) << ToString(method);
    EXPECT_NEAR(summary.x[1], 1.2, 1e-4) << ToString(method);
  }
}

TEST(BoundedMinimizer, GlobalStageEscapesALocalMinimumThatTrapsTheLocalMethod) {
  // Two wells: a shallow one at 0.2 next to the start and the deep one at 0.8.
  auto objective = [](std::span<const double> x) {
    return -0.5 * std::exp(-std::pow((x[0] - 0.2) / 0.05, 2)) -
           1.0 * std::exp(-std::pow((x[0] - 0.8) / 0.05, 2));
  };
  const BoundedMinimizer local_only({0.0}, {1.0});
  EXPECT_NEAR(local_only.Minimize(objective, {0.2}).x[0], 0.2, 1e-3);

  MinimizerOptions options;
  options.global_evaluations = 40;
  const BoundedMinimizer with_global({0.0}, {1.0}, options);
  const auto summary = with_global.Minimize(objective, {0.2});
  EXPECT_NEAR(summary.x[0], 0.8, 1e-3);
  EXPECT_GT(summary.global_evaluations, 0);
  EXPECT_LE(summary.global_evaluations, 40);
}

TEST(BoundedMinimizer, ReportsAnExhaustedBudget) {
  MinimizerOptions options;
  options.max_evaluations = 5;
  const BoundedMinimizer minimizer({-2.0, -1.0}, {2.0, 3.0}, options);
  const auto summary = minimizer.Minimize(
      [](std::span<const double> x) {
        return 100 * std::pow(x[1] - x[0] * x[0], 2) + std::pow(1 - x[0], 2);
      },
      {-1.2, 1.0});
  EXPECT_EQ(summary.stop, MinimizerStop::kMaxEvaluationsReached);
  EXPECT_EQ(summary.evaluations, 5);
  EXPECT_FALSE(IsConverged(summary.stop));
}

TEST(BoundedMinimizer, RethrowsTheObjectivesExceptionUnchanged) {
  const BoundedMinimizer minimizer({0.0}, {1.0});
  EXPECT_THROW(minimizer.Minimize(
                   [](std::span<const double>) -> double { throw InputError("simulated"); }, {0.5}),
               InputError);
}

TEST(BoundedMinimizer, RejectsInvertedBoundsAndBadBudgets) {
  EXPECT_THROW(BoundedMinimizer({1.0}, {0.0}), ConfigError);
  EXPECT_THROW(BoundedMinimizer({0.0}, {1.0, 2.0}), ConfigError);
  MinimizerOptions options;
  options.global_evaluations = options.max_evaluations;
  EXPECT_THROW(BoundedMinimizer({0.0}, {1.0}, options), ConfigError);
}

TEST(LocalMethod, NamesRoundTrip) {
  for (auto method : {LocalMethod::kBobyqa, LocalMethod::kCobyla, LocalMethod::kNelderMead}) {
    EXPECT_EQ(LocalMethodFromString(ToString(method)), method);
  }
  EXPECT_THROW(LocalMethodFromString("newton"), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
