#include "model_adequacy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "scatter_posterior.h"

namespace bouncecal::calibrate::internal {
namespace {

constexpr double kLevel = 0.99;

// z with P(Z > z) = tail for a standard normal Z, by bisection on erfc (tails far below what
// 1 - tail can hold in a double, up to 37 sigma).
double NormalUpperQuantile(double tail) {
  double low = 0, high = 40;
  for (int i = 0; i < 200; ++i) {
    const double middle = 0.5 * (low + high);
    (0.5 * std::erfc(middle / std::numbers::sqrt2) > tail ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

}  // namespace

ModelAdequacy TestSpeedTrend(const std::vector<AdequacyImpact>& impacts,
                             const AdequacyContext& context) {
  ModelAdequacy result;
  result.impacts = static_cast<int>(impacts.size());
  const ScatterPosterior fit = FitScatterPosterior(impacts, /*with_slope=*/true);
  if (fit.dof < 2) {
    result.message = "not tested: " + std::to_string(impacts.size()) +
                     " measured energy losses are too few to see a trend with impact speed";
    return result;
  }
  if (!fit.ok) {
    result.message = "not tested: every impact of a recording came in at the same speed";
    return result;
  }
  result.tested = true;
  result.slope_per_ln_speed = fit.SlopeMean();
  result.slope_uncertainty_per_ln_speed = fit.SlopeSd();
  result.speed_min_mps = fit.speed_min_mps;
  result.speed_max_mps = fit.speed_max_mps;
  result.change_over_range =
      result.slope_per_ln_speed * std::log(fit.speed_max_mps / fit.speed_min_mps);
  const double above = fit.SlopeAboveZero();
  result.trend = fit.SlopeExcludesZero(kLevel);
  const double sigmas = NormalUpperQuantile(std::min(above, 1 - above));

  char figures[200];
  std::snprintf(figures, sizeof figures, "by %+.3g from %.2g to %.2g m/s (%.1f sigma, %d impacts)",
                result.change_over_range, result.speed_min_mps, result.speed_max_mps, sigmas,
                result.impacts);
  const std::string direction = result.slope_per_ln_speed > 0 ? "rises" : "falls";
  if (!result.trend) {
    result.message = "no trend of eta_k with impact speed beyond its uncertainty (it changes " +
                     std::string(figures) + ")";
  } else if (context.comparing) {
    result.message =
        "the best-ranked law, " + context.law + ", still leaves eta_k that " + direction +
        " with impact speed " + figures +
        ": no compared law describes this material over these speeds; calibrate "
        "for the impact speeds your simulation has (fewer impacts with `first_n`, or a "
        "drop height that gives them)";
  } else if (context.speed_dependent) {
    result.message = "eta_k measured minus fitted " + direction + " with impact speed " + figures +
                     ": the speed dependence of " + context.law +
                     " does not match this material; rank the laws with `compare_laws`";
  } else {
    result.message =
        "eta_k " + direction + " with impact speed " + figures + ": one constant " +
        (context.law == "walton-braun" ? std::string("gamma_n") : context.law + " damping") +
        " does not describe this material; rank speed-dependent laws with "
        "`compare_laws`";
  }
  return result;
}

}  // namespace bouncecal::calibrate::internal
