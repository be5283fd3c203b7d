#ifndef BOUNCECAL_CALIBRATE_SRC_SANDWICH_H_
#define BOUNCECAL_CALIBRATE_SRC_SANDWICH_H_

#include <Eigen/Dense>
#include <vector>

namespace bouncecal::calibrate::internal {

// The linearised fit of one sequence at the fitted parameters x: residuals r = model - data with
// weights w = 1/sigma^2 (chi-square = sum w r^2), and how r moves with x, with the onsets and with
// the drop height; and how the onsets move when one impact's energy loss changes. The timing
// sources are each onset, then each shift common to the onsets before an impact with an
// incoming-flight uncertainty (TimedImpact), independent of one another.
struct SequenceLinearization {
  Eigen::MatrixXd parameters;      // d r / d x                  (terms x p)
  Eigen::VectorXd weights;         // 1 / sigma^2                 (terms)
  Eigen::VectorXd residual;        // r at x                      (terms)
  Eigen::MatrixXd onsets;          // d r / d t_m                 (terms x sources)
  Eigen::VectorXd onset_variance;  // stated sigma_t^2 per source (sources)
  Eigen::MatrixXd jitter;          // d t_m / d eta_k, 0 a shift  (sources x impacts)
  Eigen::VectorXd drop_height;     // sigma_h0 d r / d h0, empty when h0 is not uncertain (terms)
  int drop_height_group = 0;       // sequences of one group share one measured height
};

// Cov(x) = H^-1 M H^-1 with H = sum J'WJ (Gauss-Newton) and M = sum G C G', G = J'W (dr/dt),
// C the onsets' covariance, split by where C comes from so that each part can be scaled by its
// estimated variance: timing (stated onset variances), within (per-impact energy-loss scatter,
// unit variance, independent impacts), between (one unit offset of every impact of a sequence,
// independent sequences) and drop height (unit variance per height measurement: shared by the
// sequences of one drop_height_group, independent between groups).
struct CovarianceParts {
  bool ok = false;  // H positive definite and not ill-conditioned
  double condition = 0;
  Eigen::MatrixXd timing, within, between, drop_height;
};

// Rejects (ok = false) an H whose condition number exceeds 1e12: the parameters are then not
// separately determined by these data and no linear interval means anything.
CovarianceParts SandwichCovariance(const std::vector<SequenceLinearization>& sequences);

// One Gauss-Newton step of one sequence alone from x: the change of x that would fit it by itself
// (linearised). Empty when its own H is not positive definite.
Eigen::VectorXd SingleSequenceStep(const SequenceLinearization& sequence);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_SANDWICH_H_
