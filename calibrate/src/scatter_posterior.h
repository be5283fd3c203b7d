#ifndef BOUNCECAL_CALIBRATE_SRC_SCATTER_POSTERIOR_H_
#define BOUNCECAL_CALIBRATE_SRC_SCATTER_POSTERIOR_H_

#include <vector>

#include "model_adequacy.h"

namespace bouncecal::calibrate::internal {

// The one model of the measured energy losses within recordings (docs/calibration.md,
// "Uncertainty model"):
//   residual_i = a_sequence + b ln(speed_i) + eps_i + timing_i,
// eps_i ~ N(0, tau^2) the per-impact scatter, timing_i ~ N(0, s_i^2) with s_i the stated timing
// uncertainty of that eta_k, one intercept per sequence, with a slope a common b, and, where the
// impacts carry a contact_sensitivity d_i, a term c d_i with c ~ N(0, 1) (the simulated drop's
// contact duration as a nuisance of both the trend and the scatter, model_adequacy.h). The
// intercepts and slope have a flat prior and are integrated out, which leaves the restricted
// (REML) likelihood of tau (Patterson & Thompson 1971; Harville 1974); tau has the Jeffreys
// prior of that likelihood, p(tau^2) ~ sqrt(tr(P^2)), P = W - W X (X'WX)^-1 X'W, W = V^-1
// (Bodnar, Link, Arendacka, Possolo & Elster 2017, Stat Med 36:378, who show its intervals keep
// their coverage with few studies; for tau >> s_i it is 1/tau, under which b's posterior is
// exactly Student's t with impacts - columns dof). So an estimate of tau that is near 0 by chance
// keeps the larger values the data do not exclude, and two or three precise impacts cannot make
// a trend that scatter would explain.
//
// The posterior of tau is tabulated on a grid in ln tau (weights sum to 1); given tau, the
// intercepts and slope are normal with the weighted least-squares mean and covariance, so every
// posterior probability below is a finite mixture over the grid.
struct ScatterPosterior {
  bool ok = false;  // dof >= 1 and, with a slope, two distinct speeds in one sequence
  bool with_slope = false;
  int impacts = 0;
  int sequences = 0;
  int dof = 0;  // impacts - sequences - (1 with a slope)
  // The grid's nodes: tau, the factor on every stated timing sd (1 unless timing_scaled) and the
  // posterior weight of the node.
  std::vector<double> tau;
  std::vector<double> timing_scale;
  std::vector<double> weight;
  bool timing_scaled = false;
  std::vector<double> slope;           // posterior mean of b given tau (with a slope)
  std::vector<double> slope_variance;  // posterior variance of b given tau
  double speed_min_mps = 0;
  double speed_max_mps = 0;

  // The p-quantile of tau and of the timing scale, p in (0, 1), from the grid's marginal
  // cumulative weights.
  double TauQuantile(double p) const;
  double TimingScaleQuantile(double p) const;
  // P(b > 0) and b's posterior mean and sd, mixed over tau.
  double SlopeAboveZero() const;
  double SlopeMean() const;
  double SlopeSd() const;
  // Does b's central `level` posterior interval exclude 0 (a two-sided test at 1 - level)?
  bool SlopeExcludesZero(double level) const;
};

// With `scale_timing`, every stated timing sd is multiplied by one unknown factor phi as well,
//   timing_i ~ N(0, phi^2 s_i^2),
// phi log-uniform on [1/8, 4] (a 16-node grid in ln phi), tau given phi as above. A detector
// states a residual-only onset's sd as a whole hop (1.8 ms) where the onset is typically 0.2 ms
// off, and a band onset's at about four times its error in intervals (the chain-coverage bench's
// drops without scatter: error over stated sd 0.27-0.28 rms), so an interval that takes the
// stated sds at face value covers 100 % there; with phi the residuals' own spread says how large
// the timing noise is (as a Birge ratio does for a weighted mean, Birge 1932, Phys Rev 40:207;
// here jointly with the scatter). Where few imprecise impacts inform phi its prior range is kept.
ScatterPosterior FitScatterPosterior(const std::vector<AdequacyImpact>& impacts, bool with_slope,
                                     bool scale_timing = false);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_SCATTER_POSTERIOR_H_
