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
  // d(simulated eta_k) / d(ln contact duration) of the fitted law's drop: where the drop
  // simulates a contact of another duration than the ball's, its eta_k (from onset intervals
  // that hold the contact, with gravity acting during it) differ from the measured ones in this
  // pattern, which is the stiffness's, not the damping's. 0: not known.
  double contact_sensitivity = 0;
};

// How the message names the law and its next step.
struct AdequacyContext {
  std::string law;               // "walton-braun"
  bool speed_dependent = false;  // the law's own restitution changes with impact speed
  bool comparing = false;        // the fit is the best of --compare-laws
};

// The trend test of ModelAdequacy on the model of scatter_posterior.h with a slope: a trend when
// b's posterior gives the other sign less than 0.5 % (a two-sided 99 % interval of b excludes 0),
// tau and its uncertainty integrated out. Its "sigma" is the normal quantile of that tail. Needs
// 2 degrees of freedom and two distinct speeds in one sequence, otherwise tested = false.
ModelAdequacy TestSpeedTrend(const std::vector<AdequacyImpact>& impacts,
                             const AdequacyContext& context);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_MODEL_ADEQUACY_H_
