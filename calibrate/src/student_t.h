#ifndef BOUNCECAL_CALIBRATE_SRC_STUDENT_T_H_
#define BOUNCECAL_CALIBRATE_SRC_STUDENT_T_H_

namespace bouncecal::calibrate::internal {

// Quantiles for the confidence intervals. Written out (no Boost in the dependency list) and
// free of global state: std::lgamma writes the global signgam, and intervals are computed on
// several threads under CompareLaws.

// The standard normal quantile: Phi(x) = p, p in (0, 1).
double NormalQuantile(double p);

// Student's t quantile with `dof` degrees of freedom (any real dof > 0; above 1e7, +infinity
// included, the normal quantile), p in (0, 1). Accurate to about 1e-10 relative.
double StudentTQuantile(double p, double dof);

// P(T <= t) for Student's t with `dof` > 0 degrees of freedom.
double StudentTCdf(double t, double dof);

// P(X <= x) for the chi-square distribution with `dof` > 0 degrees of freedom: the regularised
// lower incomplete gamma function P(dof / 2, x / 2). Accurate to about 1e-12 absolute.
double ChiSquareCdf(double x, double dof);
// Its quantile, p in (0, 1): the goodness-of-fit bounds of CompareLaws.
double ChiSquareQuantile(double p, double dof);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_STUDENT_T_H_
