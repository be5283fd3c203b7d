#include "model_adequacy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "student_t.h"

namespace bouncecal::calibrate::internal {
namespace {

constexpr double kLevel = 0.99;

struct Line {
  double slope = 0;
  double slope_variance = 0;
  double weighted_squares = 0;  // sum of residual^2 / variance about the fitted lines
  bool ok = false;
};

// Weighted least squares with one intercept per sequence and, with a slope, a common slope, at a
// given tau^2.
Line FitLines(const std::vector<AdequacyImpact>& impacts, double tau_squared, bool with_slope) {
  std::map<int, std::pair<double, double>> sums;  // sequence -> (sum w v, sum w d)
  std::map<int, double> weight_sums;
  for (const auto& impact : impacts) {
    const double w = 1.0 / (tau_squared + impact.timing_variance);
    sums[impact.sequence].first += w * std::log(impact.speed_mps);
    sums[impact.sequence].second += w * impact.residual;
    weight_sums[impact.sequence] += w;
  }
  double sxx = 0, sxy = 0;
  for (const auto& impact : impacts) {
    const double w = 1.0 / (tau_squared + impact.timing_variance);
    const double total = weight_sums[impact.sequence];
    const double dv = std::log(impact.speed_mps) - sums[impact.sequence].first / total;
    const double dd = impact.residual - sums[impact.sequence].second / total;
    sxx += w * dv * dv;
    sxy += w * dv * dd;
  }
  Line line;
  if (with_slope) {
    if (!(sxx > 0)) return line;
    line.slope = sxy / sxx;
    line.slope_variance = 1.0 / sxx;
  }
  line.ok = true;
  for (const auto& impact : impacts) {
    const double w = 1.0 / (tau_squared + impact.timing_variance);
    const double total = weight_sums[impact.sequence];
    const double dv = std::log(impact.speed_mps) - sums[impact.sequence].first / total;
    const double dd = impact.residual - sums[impact.sequence].second / total;
    const double e = dd - line.slope * dv;
    line.weighted_squares += w * e * e;
  }
  return line;
}

}  // namespace

SpeedTrendFit FitSpeedTrend(const std::vector<AdequacyImpact>& impacts, bool with_slope) {
  SpeedTrendFit fit;
  std::map<int, int> per_sequence;
  for (const auto& impact : impacts) ++per_sequence[impact.sequence];
  fit.impacts = static_cast<int>(impacts.size());
  fit.sequences = static_cast<int>(per_sequence.size());
  fit.dof = fit.impacts - fit.sequences - (with_slope ? 1 : 0);
  if (fit.dof < 1) return fit;
  // A zero timing variance (hand-made impact times) would make a weight infinite at tau = 0.
  std::vector<AdequacyImpact> data = impacts;
  for (auto& impact : data) {
    impact.timing_variance = std::max(impact.timing_variance, 1e-14);
    impact.speed_mps = std::max(impact.speed_mps, 1e-9);  // its logarithm is the regressor
  }
  Line line = FitLines(data, 0, with_slope);
  if (!line.ok) return fit;
  // Paule-Mandel: the tau^2 >= 0 with weighted squares = dof; they fall as tau^2 grows.
  if (line.weighted_squares > fit.dof) {
    double low = 0, high = 1e-6;
    while (FitLines(data, high, with_slope).weighted_squares > fit.dof && high < 1e6) high *= 4;
    for (int i = 0; i < 100; ++i) {
      const double middle = 0.5 * (low + high);
      (FitLines(data, middle, with_slope).weighted_squares > fit.dof ? low : high) = middle;
    }
    fit.tau_squared = high;
    line = FitLines(data, fit.tau_squared, with_slope);
  }
  fit.ok = true;
  fit.slope = line.slope;
  fit.slope_variance = line.slope_variance;
  fit.speed_min_mps = fit.speed_max_mps = data.front().speed_mps;
  for (const auto& impact : data) {
    fit.speed_min_mps = std::min(fit.speed_min_mps, impact.speed_mps);
    fit.speed_max_mps = std::max(fit.speed_max_mps, impact.speed_mps);
  }
  return fit;
}

ModelAdequacy TestSpeedTrend(const std::vector<AdequacyImpact>& impacts,
                             const AdequacyContext& context) {
  ModelAdequacy result;
  result.impacts = static_cast<int>(impacts.size());
  const SpeedTrendFit fit = FitSpeedTrend(impacts, /*with_slope=*/true);
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
  result.slope_per_ln_speed = fit.slope;
  result.slope_uncertainty_per_ln_speed = std::sqrt(fit.slope_variance);
  result.speed_min_mps = fit.speed_min_mps;
  result.speed_max_mps = fit.speed_max_mps;
  result.change_over_range = fit.slope * std::log(fit.speed_max_mps / fit.speed_min_mps);
  const double sigmas = std::fabs(fit.slope) / result.slope_uncertainty_per_ln_speed;
  result.trend = sigmas > StudentTQuantile(0.5 + kLevel / 2, fit.dof);

  char figures[200];
  std::snprintf(figures, sizeof figures, "by %+.3g from %.2g to %.2g m/s (%.1f sigma, %d impacts)",
                result.change_over_range, result.speed_min_mps, result.speed_max_mps, sigmas,
                result.impacts);
  const std::string direction = fit.slope > 0 ? "rises" : "falls";
  if (!result.trend) {
    result.message = "no trend of eta_k with impact speed beyond its uncertainty (it changes " +
                     std::string(figures) + ")";
  } else if (context.comparing) {
    result.message = "the best-ranked law, " + context.law + ", still leaves eta_k that " +
                     direction + " with impact speed " + figures +
                     ": no compared law describes this material over these speeds; calibrate "
                     "for the impact speeds your simulation has (--first N, or a drop height "
                     "that gives them)";
  } else if (context.speed_dependent) {
    result.message = "eta_k measured minus fitted " + direction + " with impact speed " + figures +
                     ": the speed dependence of " + context.law +
                     " does not match this material; rank the laws with --compare-laws";
  } else {
    result.message =
        "eta_k " + direction + " with impact speed " + figures + ": one constant " +
        (context.law == "walton-braun" ? std::string("gamma_n") : context.law + " damping") +
        " does not describe this material; rank speed-dependent laws with "
        "--compare-laws";
  }
  return result;
}

}  // namespace bouncecal::calibrate::internal
