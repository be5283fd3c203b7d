#ifndef BOUNCECAL_CALIBRATE_SRC_MODEL_ADEQUACY_H_
#define BOUNCECAL_CALIBRATE_SRC_MODEL_ADEQUACY_H_

#include <string>
#include <vector>

#include "bouncecal/calibrate/uncertainty.h"

namespace bouncecal::calibrate::internal {

// One measured impact: the speed it came in with, eta_k measured minus the fitted law's, and the
// variance timing noise gives that eta_k.
struct AdequacyImpact {
  int sequence = 0;
  double speed_mps = 0;
  double residual = 0;
  double timing_variance = 0;
};

// Residual_i = a_sequence + b ln(speed_i) + noise_i with Var(noise_i) = tau^2 + timing_variance_i:
// one intercept per sequence and, with `with_slope`, a common slope, fitted by weighted least
// squares with tau^2 chosen so the weighted residual sum of squares equals its degrees of freedom
// (Paule & Mandel 1982; 0 when timing alone explains the scatter).
struct SpeedTrendFit {
  bool ok = false;  // enough impacts (dof >= 1) and, with a slope, two speeds in one sequence
  int impacts = 0;
  int sequences = 0;
  int dof = 0;  // impacts - sequences - (1 with a slope)
  double slope = 0;
  double slope_variance = 0;
  double tau_squared = 0;  // per-impact scatter beyond timing noise, about the lines
  double speed_min_mps = 0;
  double speed_max_mps = 0;
};
SpeedTrendFit FitSpeedTrend(const std::vector<AdequacyImpact>& impacts, bool with_slope);

// How the message names the law and its next step.
struct AdequacyContext {
  std::string law;               // "walton-braun"
  bool speed_dependent = false;  // the law's own restitution changes with impact speed
  bool comparing = false;        // the fit is the best of --compare-laws
};

// The trend test of ModelAdequacy on FitSpeedTrend(impacts, true): the slope is significant when
// |b| / se(b) exceeds Student's t at 0.995 with its degrees of freedom. Needs 2 of them and two
// distinct speeds in one sequence, otherwise tested = false.
ModelAdequacy TestSpeedTrend(const std::vector<AdequacyImpact>& impacts,
                             const AdequacyContext& context);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_MODEL_ADEQUACY_H_
