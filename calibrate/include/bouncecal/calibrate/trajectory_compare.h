#ifndef BOUNCECAL_CALIBRATE_TRAJECTORY_COMPARE_H_
#define BOUNCECAL_CALIBRATE_TRAJECTORY_COMPARE_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// Height of the ball's lowest point against time from the release (t = 0).
struct HeightCurve {
  std::vector<double> time_s;
  std::vector<double> height_m;
};

// The measured trajectory rebuilt as ballistic arcs from the onsets (the paper's Fig. 5): the fall
// from h0 before the first impact, then h(t) = g (t - t_k)(t_{k+1} - t) / 2 between impacts k and
// k+1. The onsets are shifted so the first impact falls at sqrt(2 h0 / g) after the release.
// Sampled every sample_interval_s. Throws ConfigError for fewer than 2 onsets or bad numbers.
HeightCurve MeasuredTrajectory(const std::vector<double>& onsets_s, double drop_height_m,
                               double gravity_mps2, double sample_interval_s);

// RMS of measured - simulated height on the measured samples up to the last measured impact;
// the simulated curve is interpolated linearly (and 0 after its end: the ball at rest).
double RmsHeightError(const HeightCurve& measured, const HeightCurve& simulated);

struct TrajectoryCompareOptions {
  std::vector<dem::ContactLawConfig> laws;  // one simulated curve each
  // The simulated drop set-up (ball, release height, gravity, drag, integrator, step) for every
  // law; its own law is replaced by each of `laws`.
  dem::DropOptions drop;
  double sample_interval_s = 5e-4;  // 0.5 ms resolves the last, ~10 ms flights
};

struct SimulatedCurve {
  dem::ContactLawConfig law;
  HeightCurve curve;
  double rms_height_error_m = 0;
};

struct TrajectoryCompareSummary {
  HeightCurve measured;
  std::vector<SimulatedCurve> simulated;
};

TrajectoryCompareSummary CompareTrajectories(const std::vector<double>& onsets_s,
                                             const TrajectoryCompareOptions& options);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_TRAJECTORY_COMPARE_H_
