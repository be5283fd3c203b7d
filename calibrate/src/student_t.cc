#include "student_t.h"

#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

namespace bouncecal::calibrate::internal {
namespace {

// Beyond this the t distribution is the normal to within (z^3 + z) / (4 dof) < 3e-7 at the
// quantiles used here, while ln Gamma(dof / 2) differences lose all precision (Satterthwaite's
// effective dof reach 1e30 when timing noise dominates).
constexpr double kNormalDof = 1e7;

// ln Gamma(x) for x > 0: Lanczos (g = 7, n = 9; the coefficients of Numerical Recipes 3rd ed.
// section 6.1 / Godfrey), relative error below 1e-15, with the reflection-free shift for x < 0.5.
double LogGamma(double x) {
  static constexpr double kCoefficients[9] = {
      0.99999999999980993,  676.5203681218851,     -1259.1392167224028,
      771.32342877765313,   -176.61502916214059,   12.507343278686905,
      -0.13857109526572012, 9.9843695780195716e-6, 1.5056327351493116e-7};
  if (x < 0.5) return LogGamma(x + 1) - std::log(x);
  x -= 1;
  double sum = kCoefficients[0];
  for (int i = 1; i < 9; ++i) sum += kCoefficients[i] / (x + i);
  const double t = x + 7.5;
  return 0.5 * std::log(2 * std::numbers::pi) + (x + 0.5) * std::log(t) - t + std::log(sum);
}

// Continued fraction of the regularised incomplete beta function (modified Lentz), valid for
// x < (a + 1) / (a + b + 2).
double BetaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1 / d;
  double result = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double numerator = m * (b - m) * x / ((a + m2 - 1) * (a + m2));
    d = 1 + numerator * d;
    c = 1 + numerator / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1 / d;
    result *= d * c;
    numerator = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1));
    d = 1 + numerator * d;
    c = 1 + numerator / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double step = d * c;
    result *= step;
    if (std::fabs(step - 1) < 1e-16) break;
  }
  return result;
}

// I_x(a, b).
double RegularizedBeta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double log_front =
      LogGamma(a + b) - LogGamma(a) - LogGamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double front = std::exp(log_front);
  if (x < (a + 1) / (a + b + 2)) return front * BetaContinuedFraction(a, b, x) / a;
  return 1 - front * BetaContinuedFraction(b, a, 1 - x) / b;
}

// Solves cdf(x) = p by bisection on a bracket grown from [0, 1]: slow-ish (about 100 cdf
// evaluations) but needs no derivative and cannot diverge.
template <typename Cdf>
double InvertIncreasing(Cdf cdf, double p) {
  double low = 0, high = 1;
  while (cdf(high) < p && high < 1e300) {
    low = high;
    high *= 2;
  }
  for (int i = 0; i < 200 && high - low > 1e-13 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (cdf(middle) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

// P(a, x) by its series for x < a + 1 and by the continued fraction of Q(a, x) (modified Lentz)
// beyond (Numerical Recipes 3rd ed. section 6.2): both converge fast in their range.
double RegularizedLowerGamma(double a, double x) {
  if (x <= 0) return 0;
  const double log_front = a * std::log(x) - x - LogGamma(a);
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n <= 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < 1e-16 * std::fabs(sum)) break;
    }
    return sum * std::exp(log_front);
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, fraction = d;
  for (int i = 1; i <= 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double step = d * c;
    fraction *= step;
    if (std::fabs(step - 1) < 1e-16) break;
  }
  return 1 - std::exp(log_front) * fraction;
}

}  // namespace

double NormalQuantile(double p) {
  assert(p > 0 && p < 1);
  if (p < 0.5) return -NormalQuantile(1 - p);
  return InvertIncreasing(NormalCdf, p);
}

double StudentTCdf(double t, double dof) {
  assert(dof > 0);
  if (dof > kNormalDof) return NormalCdf(t);
  const double tail = 0.5 * RegularizedBeta(dof / 2, 0.5, dof / (dof + t * t));
  return t >= 0 ? 1 - tail : tail;
}

double StudentTQuantile(double p, double dof) {
  assert(p > 0 && p < 1 && dof > 0);
  if (dof > kNormalDof) return NormalQuantile(p);
  if (p < 0.5) return -StudentTQuantile(1 - p, dof);
  return InvertIncreasing([dof](double t) { return StudentTCdf(t, dof); }, p);
}

double ChiSquareCdf(double x, double dof) {
  assert(dof > 0);
  return RegularizedLowerGamma(dof / 2, x / 2);
}

double ChiSquareQuantile(double p, double dof) {
  assert(p > 0 && p < 1 && dof > 0);
  return InvertIncreasing([dof](double x) { return ChiSquareCdf(x, dof); }, p);
}

}  // namespace bouncecal::calibrate::internal
