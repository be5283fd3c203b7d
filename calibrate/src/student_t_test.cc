#include "student_t.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace bouncecal::calibrate::internal {
namespace {

TEST(StudentT, QuantilesMatchTheTables) {
  // Two-sided 95 % critical values (e.g. Abramowitz & Stegun table 26.10), to the 4 decimals
  // printed there.
  const std::pair<double, double> table[] = {{1, 12.7062}, {2, 4.3027},  {3, 3.1824},
                                             {4, 2.7764},  {5, 2.5706},  {10, 2.2281},
                                             {30, 2.0423}, {120, 1.9799}};
  for (const auto& [dof, quantile] : table)
    EXPECT_NEAR(StudentTQuantile(0.975, dof), quantile, 5e-5) << dof;
  EXPECT_NEAR(StudentTQuantile(0.995, 10), 3.1693, 5e-5);
  EXPECT_NEAR(StudentTQuantile(0.025, 4), -2.7764, 5e-5);
}

TEST(StudentT, OneAndTwoDegreesOfFreedomHaveClosedForms) {
  // dof 1 is Cauchy: t = tan(pi (p - 1/2)); dof 2: t = (2p - 1) sqrt(2 / (4 p (1 - p))).
  for (double p : {0.6, 0.9, 0.975, 0.999}) {
    EXPECT_NEAR(StudentTQuantile(p, 1), std::tan(M_PI * (p - 0.5)),
                1e-9 * std::tan(M_PI * (p - 0.5)));
    const double two = (2 * p - 1) * std::sqrt(2 / (4 * p * (1 - p)));
    EXPECT_NEAR(StudentTQuantile(p, 2), two, 1e-9 * two);
  }
}

TEST(StudentT, InfiniteDegreesOfFreedomIsTheNormal) {
  EXPECT_NEAR(NormalQuantile(0.975), 1.959963984540054, 1e-10);
  EXPECT_NEAR(NormalQuantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(NormalQuantile(0.001), -3.090232306167814, 1e-9);
  EXPECT_EQ(StudentTQuantile(0.975, std::numeric_limits<double>::infinity()),
            NormalQuantile(0.975));
  // A million degrees of freedom is indistinguishable from the normal at 1e-5, and astronomically
  // many (Satterthwaite's when timing dominates) must not lose precision on the way.
  EXPECT_NEAR(StudentTQuantile(0.975, 1e6), NormalQuantile(0.975), 1e-5);
  EXPECT_NEAR(StudentTQuantile(0.975, 5e6), NormalQuantile(0.975), 1e-6);
  EXPECT_EQ(StudentTQuantile(0.975, 1e30), NormalQuantile(0.975));
}

TEST(StudentT, FractionalDegreesOfFreedomLieBetweenTheirNeighbours) {
  // Satterthwaite's effective degrees of freedom are not integers.
  const double q = StudentTQuantile(0.975, 2.5);
  EXPECT_LT(q, StudentTQuantile(0.975, 2));
  EXPECT_GT(q, StudentTQuantile(0.975, 3));
  EXPECT_NEAR(StudentTCdf(q, 2.5), 0.975, 1e-10);
}

TEST(ChiSquare, QuantilesMatchTheTables) {
  // Central 99 % bounds (0.5 % and 99.5 % points; Abramowitz & Stegun table 26.8 / NIST
  // e-Handbook 1.3.6.7.4), to the 3 decimals printed there.
  const struct {
    double dof, low, high;
  } table[] = {{1, 0.0000393, 7.879}, {2, 0.010, 10.597},   {5, 0.412, 16.750},
               {10, 2.156, 25.188},   {30, 13.787, 53.672}, {100, 67.328, 140.169}};
  for (const auto& row : table) {
    EXPECT_NEAR(ChiSquareQuantile(0.005, row.dof), row.low, 5e-4 + 1e-4 * row.low) << row.dof;
    EXPECT_NEAR(ChiSquareQuantile(0.995, row.dof), row.high, 5e-4 + 1e-4 * row.high) << row.dof;
  }
}

TEST(ChiSquare, TwoDegreesOfFreedomIsTheExponential) {
  // chi-square with 2 dof: P(X <= x) = 1 - exp(-x / 2), both sides of the series/fraction switch.
  for (double x : {0.01, 0.5, 1.9, 2.1, 10.0, 60.0})
    EXPECT_NEAR(ChiSquareCdf(x, 2), -std::expm1(-x / 2), 1e-13) << x;
  // One dof: P(X <= x) = erf(sqrt(x / 2)).
  for (double x : {0.1, 1.0, 3.84, 20.0})
    EXPECT_NEAR(ChiSquareCdf(x, 1), std::erf(std::sqrt(x / 2)), 1e-13) << x;
  EXPECT_EQ(ChiSquareCdf(0, 3), 0);
}

}  // namespace
}  // namespace bouncecal::calibrate::internal
