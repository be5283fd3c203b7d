#include "sequences/ratio_scatter.h"

#include <Eigen/Dense>
#include <cmath>
#include <cstddef>

namespace bouncecal::audio {

namespace {

// Upper tail of the chi-square distribution with `dof` degrees of freedom: (chi2/dof)^(1/3) is
// nearly normal (Wilson and Hilferty 1931); within a factor of ~4 of the exact tail at 1e-6 for
// one degree of freedom and closer for more, which is all a refusal at a small chance needs.
double ChiSquareTail(double chi2, int dof) {
  const double k = static_cast<double>(dof);
  const double spread = 2.0 / (9.0 * k);
  const double z = (std::cbrt(chi2 / k) - (1.0 - spread)) / std::sqrt(spread);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace

double ChanceOfRatioScatter(const std::vector<Impact>& impacts, const std::vector<int>& members,
                            double relative_scatter) {
  const std::size_t n = members.size();
  if (n < 5) return 1.0;
  const std::size_t m = n - 2;  // ratios
  Eigen::VectorXd onset(n), variance(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Impact& impact = impacts[static_cast<std::size_t>(members[k])];
    onset[static_cast<Eigen::Index>(k)] = impact.onset_s;
    variance[static_cast<Eigen::Index>(k)] =
        impact.onset_uncertainty_s * impact.onset_uncertainty_s;
  }
  // r_k = (t_{k+2} - t_{k+1}) / (t_{k+1} - t_k) and its derivatives in the three onsets.
  Eigen::VectorXd ratio(m);
  Eigen::MatrixXd jacobian =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n));
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(m); ++k) {
    const double before = onset[k + 1] - onset[k];
    const double after = onset[k + 2] - onset[k + 1];
    if (!(before > 0) || !(after > 0)) return 1.0;
    ratio[k] = after / before;
    jacobian(k, k + 2) = 1.0 / before;
    jacobian(k, k + 1) = -1.0 / before - after / (before * before);
    jacobian(k, k) = after / (before * before);
  }
  Eigen::MatrixXd covariance = jacobian * variance.asDiagonal() * jacobian.transpose();
  covariance.diagonal() += (relative_scatter * ratio).cwiseAbs2();
  const Eigen::LLT<Eigen::MatrixXd> cholesky(covariance);
  if (cholesky.info() != Eigen::Success) return 1.0;
  Eigen::MatrixXd line(static_cast<Eigen::Index>(m), 2);
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(m); ++k) {
    line(k, 0) = 1.0;
    line(k, 1) = static_cast<double>(k);
  }
  // Whitened, the generalised least squares fit is an ordinary one.
  const Eigen::MatrixXd whitened_line = cholesky.matrixL().solve(line);
  const Eigen::VectorXd whitened_ratio = cholesky.matrixL().solve(ratio);
  const Eigen::VectorXd coefficients = whitened_line.colPivHouseholderQr().solve(whitened_ratio);
  const double chi2 = (whitened_ratio - whitened_line * coefficients).squaredNorm();
  return ChiSquareTail(chi2, static_cast<int>(m) - 2);
}

}  // namespace bouncecal::audio
