#ifndef BOUNCECAL_CALIBRATE_ANALYTIC_CHECK_H_
#define BOUNCECAL_CALIBRATE_ANALYTIC_CHECK_H_

#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/minimizer.h"
#include "fit_problem.h"

namespace bouncecal::calibrate::internal {

// The check of a fit against its law's closed form (FitSummary::check): the parameter the
// closed form gives for the measured eta-bar against the fitted one, with the difference's
// measured budget (time step, the closed form's model error, air drag, eta-bar's uncertainty)
// and, where the two disagree beyond it, the next step. `law` is the fitted law, `plans` the
// fitted recordings (the first is the simulated reference), `stop` why the optimiser stopped.
AnalyticCheck MakeCheck(const FitOptions& options, const ParameterMap& map,
                        const dem::ContactLawConfig& law, const std::vector<SequencePlan>& plans,
                        const UncertaintySummary& uncertainty, MinimizerStop stop);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_ANALYTIC_CHECK_H_
