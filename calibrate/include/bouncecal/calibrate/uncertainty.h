#ifndef BOUNCECAL_CALIBRATE_UNCERTAINTY_H_
#define BOUNCECAL_CALIBRATE_UNCERTAINTY_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bouncecal::calibrate {

// What a fit's confidence intervals include, and the figures behind them (docs/calibration.md,
// "Uncertainty model"). The data are modelled as
//   eta_rk = eta_k(theta) + b_r + eps_rk + (onset timing noise),
// eta_rk the energy loss of impact k of recording r, eta_k(theta) the fitted law's simulated value,
// eps_rk independent per-impact scatter (sd tau_w: impact point, spin, surface), b_r a recording's
// common offset (sd tau_b: re-mounting, another spot on the plate), and each onset's stated timing
// noise. tau_w has a posterior from every measured impact (REML likelihood with each eta_k's own
// timing variance, Jeffreys prior; one intercept per recording and a speed slope when the trend
// test claims one), tau_b a moment estimate from the spread of the recordings' means net of what
// tau_w and timing explain. Each component moves the onsets (a restitution change at impact k
// stretches every later flight), the onsets move the objective's residuals, and the residuals move
// the fitted parameters: the Jacobians come from DEM drops at the fit, and the parameters'
// covariance is the Gauss-Newton sandwich H^-1 J^T W C W J H^-1 (Eigen). Given tau_w the interval
// is Student t with Satterthwaite's degrees of freedom of tau_b; it is mixed over tau_w's
// posterior, since tau_w is estimated from few impacts.
struct RecordingSpread {
  std::string source;
  int impacts_used = 0;
  double energy_loss_mean = 0;              // eta-bar of the used impacts
  double energy_loss_mean_uncertainty = 0;  // one sigma: tau_w^2 / n + timing
  double energy_loss_scatter = 0;           // sd of this recording's eta_k about the fitted law
  // The fitted parameters from this recording alone, linearised about the joint fit (one
  // Gauss-Newton step); empty when this recording alone does not determine them.
  std::vector<double> parameter_values;
};

struct UncertaintySummary {
  bool available = false;
  std::string message;  // why not, when unavailable
  // One sentence: what the intervals include, with the figures.
  std::string model;
  double confidence_level = 0.95;

  int sequences = 0;   // distinct bounce sequences fitted
  int duplicates = 0;  // sequences dropped as duplicates of another (identical impact times)
  int impacts_used = 0;

  // Per-impact scatter of eta_k beyond timing noise (tau_w: its posterior median) and its degrees
  // of freedom.
  double per_impact_scatter = 0;
  int per_impact_dof = 0;
  bool per_impact_estimable = false;  // false when every recording has a single used impact
  // Between-recording sd of eta (tau_b), estimated when there are at least two sequences.
  double between_recording_sd = 0;
  int between_dof = 0;

  // Of the first fitted parameter: the shares of its variance (sum 1), the effective degrees of
  // freedom and the t quantile of its interval.
  double timing_share = 0;
  double scatter_share = 0;
  double between_share = 0;
  double drop_height_share = 0;
  // The interval's half-width over the standard error (at the median tau_w), and the Student dof
  // with that quantile; +inf when only known variances contribute.
  double effective_dof = 0;
  double t_quantile = 0;

  // The paper's protocol across sequences: eta-bar of each, their mean, sd and the interval of the
  // mean (Student t with sequences - 1 dof); with one sequence, sd and interval are absent.
  double energy_loss_mean = 0;
  double energy_loss_mean_uncertainty = 0;  // one sigma of the mean, every component
  std::optional<double> energy_loss_sd_across;
  std::optional<std::pair<double, double>> energy_loss_mean_interval;
  std::vector<RecordingSpread> recordings;
};

// Does eta_k change with impact speed beyond its uncertainty? A weighted straight line of the
// residuals (measured minus fitted eta_k) against the logarithm of the speed into each impact
// (restitution laws are power laws in speed: 1 - e ~ v^(1/5) for viscoelastic Hertz), one
// intercept per recording, the per-impact scatter integrated over its posterior, tested at the
// 99 % level (a 1 % false alarm rate on a law that does describe the data). Every measured impact
// takes part, not only the fitted ones: the question is whether the law carries over to other
// impact speeds.
struct ModelAdequacy {
  bool tested = false;
  int impacts = 0;
  double speed_min_mps = 0;
  double speed_max_mps = 0;
  double slope_per_ln_speed = 0;  // d(eta residual) / d ln v
  double slope_uncertainty_per_ln_speed = 0;
  double change_over_range = 0;  // slope * ln(max / min speed)
  bool trend = false;
  std::string message;  // one sentence; with a trend it names the next step
};

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_UNCERTAINTY_H_
