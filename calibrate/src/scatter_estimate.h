#ifndef BOUNCECAL_CALIBRATE_SRC_SCATTER_ESTIMATE_H_
#define BOUNCECAL_CALIBRATE_SRC_SCATTER_ESTIMATE_H_

#include <Eigen/Dense>
#include <vector>

#include "scatter_posterior.h"

namespace bouncecal::calibrate::internal {

// The used impacts of one sequence: eta_k measured minus eta_k of the fitted law, and the
// covariance of the measured eta_k that onset timing noise alone produces (neighbouring eta_k
// share onsets, so it is not diagonal).
struct ImpactResiduals {
  Eigen::VectorXd residual;
  Eigen::MatrixXd timing_covariance;
};

// Variance components of eta beyond timing noise (method of moments, one-way random effects):
//  - within: per-impact scatter tau_w^2. From every measured impact when `every_impact` is given
//    and ok: its posterior (scatter_posterior.h), kept whole for the interval, with the median
//    tau^2 as the point value and its dof. Otherwise (method of moments) from the used impacts,
//    pooled over the sequences from the deviations about each sequence's mean residual, minus what
//    timing explains: E[sum_k (d_k - dbar)^2] = (n - 1) tau_w^2 + tr(V) - 1'V1/n; degrees of
//    freedom sum (n_r - 1) - (p - 1), p the fitted parameters (a law with p > 1 can bend to the
//    impacts, a constant one only shift);
//  - between: the spread of the sequences' mean residuals beyond what tau_w^2 / n_r and timing
//    give them, tau_b^2, with (sequences - 1) degrees of freedom; needs two sequences.
// Moment estimates are truncated at 0 (DerSimonian & Laird 1986 do the same).
struct ScatterEstimate {
  double within_variance = 0;
  int within_dof = 0;
  bool within_estimable = false;  // some sequence has two used impacts and dof >= 1
  bool within_from_every_impact = false;
  ScatterPosterior within_posterior;  // ok when within_from_every_impact
  // The factor on every stated timing variance at the point value: the posterior median of
  // phi^2 where within_posterior scales the timing (scatter_posterior.h), otherwise 1.
  double timing_variance_scale = 1;
  double between_variance = 0;
  int between_dof = 0;
  // What between_variance was computed from: the sample variance of the sequences' mean
  // residuals, and the part of it that within-sequence scatter and timing explain,
  // within_variance * mean(1 / n_r) + mean(timing variance of each mean).
  double between_mean_square = 0;
  double mean_inverse_count = 0;
  double mean_timing_variance = 0;
};

ScatterEstimate EstimateScatter(const std::vector<ImpactResiduals>& sequences,
                                int fitted_parameters,
                                const ScatterPosterior* every_impact = nullptr);

// The timing variance of a sequence's mean residual, 1'V1 / n^2.
double TimingVarianceOfMean(const ImpactResiduals& sequence);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_SCATTER_ESTIMATE_H_
