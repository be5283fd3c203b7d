#ifndef BOUNCECAL_CALIBRATE_SRC_FIT_UNCERTAINTY_H_
#define BOUNCECAL_CALIBRATE_SRC_FIT_UNCERTAINTY_H_

#include <optional>
#include <utility>
#include <vector>

#include "bouncecal/calibrate/uncertainty.h"
#include "fit_problem.h"
#include "model_adequacy.h"
#include "scatter_estimate.h"

namespace bouncecal::calibrate::internal {

struct ParameterUncertainty {
  std::optional<std::pair<double, double>> interval;  // in the parameter's unit
  double standard_error = 0;                          // in the parameter's unit, linearised
  bool clipped = false;  // the interval reached the search range and was cut there
};

struct FitUncertainty {
  UncertaintySummary summary;
  std::vector<ParameterUncertainty> parameters;  // one per fitted parameter
};

// Every measured impact of every plan with a measured energy loss: its impact speed and eta_k
// measured minus eta_k of `law` simulated over the whole sequence (for the scatter estimate and
// the trend test).
std::vector<AdequacyImpact> EveryImpactResiduals(const std::vector<SequencePlan>& plans,
                                                 const FitOptions& options,
                                                 const dem::ContactLawConfig& law);

// The per-impact scatter of eta about the law at x (the first step of the model, also used to
// reweight a joint fit of several recordings).
ScatterEstimate ScatterAt(const std::vector<SequencePlan>& plans, const FitOptions& options,
                          const ParameterMap& map, const std::vector<double>& x);

// The uncertainty model of uncertainty.h at the fitted x of the plans' joint fit.
FitUncertainty EstimateUncertainty(const std::vector<SequencePlan>& plans,
                                   const FitOptions& options, const ParameterMap& map,
                                   const std::vector<double>& x);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_FIT_UNCERTAINTY_H_
