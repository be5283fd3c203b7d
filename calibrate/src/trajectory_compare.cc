#include "bouncecal/calibrate/trajectory_compare.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {

HeightCurve MeasuredTrajectory(const std::vector<double>& onsets_s, double drop_height_m,
                               double gravity_mps2, double sample_interval_s) {
  if (onsets_s.size() < 2) {
    throw ConfigError("a measured trajectory needs at least 2 impact onsets, got " +
                      std::to_string(onsets_s.size()));
  }
  if (!(drop_height_m > 0) || !(gravity_mps2 > 0) || !(sample_interval_s > 0)) {
    throw ConfigError("drop height, gravity and sample interval must be positive");
  }
  const double g = gravity_mps2;
  const double shift = std::sqrt(2 * drop_height_m / g) - onsets_s.front();
  std::vector<double> onsets;
  for (double onset : onsets_s) onsets.push_back(onset + shift);
  HeightCurve curve;
  const double end = onsets.back();
  size_t k = 0;
  const int samples = static_cast<int>(std::ceil(end / sample_interval_s));
  for (int i = 0; i <= samples; ++i) {
    const double t = std::min(i * sample_interval_s, end);
    while (k < onsets.size() && onsets[k] <= t) ++k;
    double height = 0;
    if (k == 0) {
      height = drop_height_m - 0.5 * g * t * t;
    } else if (k < onsets.size()) {
      height = 0.5 * g * (t - onsets[k - 1]) * (onsets[k] - t);
    }
    curve.time_s.push_back(t);
    curve.height_m.push_back(std::max(height, 0.0));
  }
  return curve;
}

double RmsHeightError(const HeightCurve& measured, const HeightCurve& simulated) {
  if (measured.time_s.empty()) return 0;
  double sum = 0;
  size_t j = 0;
  for (size_t i = 0; i < measured.time_s.size(); ++i) {
    const double t = measured.time_s[i];
    while (j + 1 < simulated.time_s.size() && simulated.time_s[j + 1] < t) ++j;
    double height = 0;
    if (j + 1 < simulated.time_s.size()) {
      const double t0 = simulated.time_s[j], t1 = simulated.time_s[j + 1];
      const double w = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 0.0;
      height = simulated.height_m[j] * (1 - w) + simulated.height_m[j + 1] * w;
    }
    const double difference = measured.height_m[i] - height;
    sum += difference * difference;
  }
  return std::sqrt(sum / static_cast<double>(measured.time_s.size()));
}

TrajectoryCompareSummary CompareTrajectories(const std::vector<double>& onsets_s,
                                             const TrajectoryCompareOptions& options) {
  if (options.laws.empty())
    throw OptionError({"laws"}, "no law to simulate: `laws` is empty; give at least one");
  TrajectoryCompareSummary summary;
  summary.measured = MeasuredTrajectory(onsets_s, options.drop.drop_height_m,
                                        options.drop.gravity_mps2, options.sample_interval_s);
  const double end = summary.measured.time_s.back();
  for (const auto& law : options.laws) {
    dem::DropOptions drop = options.drop;
    drop.law = law;
    drop.max_time_s = end + options.sample_interval_s;
    drop.trajectory_interval_s = options.sample_interval_s;
    const auto result = dem::SimulateDrop(drop);
    SimulatedCurve simulated;
    simulated.law = law;
    for (const auto& point : result.trajectory) {
      if (point.time_s > end) break;
      simulated.curve.time_s.push_back(point.time_s);
      simulated.curve.height_m.push_back(std::max(point.height_m, 0.0));
    }
    simulated.rms_height_error_m = RmsHeightError(summary.measured, simulated.curve);
    summary.simulated.push_back(std::move(simulated));
  }
  return summary;
}

}  // namespace bouncecal::calibrate
