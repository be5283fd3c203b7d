#include "scatter_estimate.h"

#include <algorithm>

namespace bouncecal::calibrate::internal {

double TimingVarianceOfMean(const ImpactResiduals& sequence) {
  const auto n = static_cast<double>(sequence.residual.size());
  if (n == 0) return 0;
  return sequence.timing_covariance.sum() / (n * n);
}

ScatterEstimate EstimateScatter(const std::vector<ImpactResiduals>& sequences,
                                int fitted_parameters, const ScatterPosterior* every_impact) {
  ScatterEstimate estimate;
  double excess = 0;
  int dof = 0;
  bool any_pair = false;
  for (const auto& sequence : sequences) {
    const Eigen::Index n = sequence.residual.size();
    if (n < 2) continue;
    any_pair = true;
    const double mean = sequence.residual.mean();
    const double squares = (sequence.residual.array() - mean).square().sum();
    const auto& v = sequence.timing_covariance;
    excess += squares - (v.trace() - v.sum() / static_cast<double>(n));
    dof += static_cast<int>(n) - 1;
  }
  dof -= std::max(0, fitted_parameters - 1);
  if (any_pair && dof >= 1) {
    estimate.within_estimable = true;
    estimate.within_dof = dof;
    estimate.within_variance = std::max(0.0, excess / dof);
  }
  if (every_impact && every_impact->ok) {
    estimate.within_estimable = true;
    estimate.within_from_every_impact = true;
    estimate.within_dof = every_impact->dof;
    const double median = every_impact->TauQuantile(0.5);
    estimate.within_variance = median * median;
    estimate.within_posterior = *every_impact;
    if (every_impact->timing_scaled) {
      const double phi = every_impact->TimingScaleQuantile(0.5);
      estimate.timing_variance_scale = phi * phi;
    }
  }

  const int count = static_cast<int>(sequences.size());
  if (count >= 2) {
    double sum = 0, inverse_counts = 0, timing = 0;
    for (const auto& sequence : sequences) {
      sum += sequence.residual.size() ? sequence.residual.mean() : 0.0;
      const auto n = static_cast<double>(std::max<Eigen::Index>(sequence.residual.size(), 1));
      inverse_counts += 1 / n;
      timing += TimingVarianceOfMean(sequence);
    }
    estimate.mean_inverse_count = inverse_counts / count;
    estimate.mean_timing_variance = timing / count;
    const double expected = estimate.within_variance * estimate.mean_inverse_count +
                            estimate.timing_variance_scale * estimate.mean_timing_variance;
    const double grand = sum / count;
    double spread = 0;
    for (const auto& sequence : sequences) {
      const double mean = sequence.residual.size() ? sequence.residual.mean() : 0.0;
      spread += (mean - grand) * (mean - grand);
    }
    estimate.between_dof = count - 1;
    estimate.between_mean_square = spread / (count - 1);
    estimate.between_variance = std::max(0.0, estimate.between_mean_square - expected);
  }
  return estimate;
}

}  // namespace bouncecal::calibrate::internal
