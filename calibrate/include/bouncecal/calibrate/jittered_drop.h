#ifndef BOUNCECAL_CALIBRATE_JITTERED_DROP_H_
#define BOUNCECAL_CALIBRATE_JITTERED_DROP_H_

#include <cstdint>

#include "bouncecal/calibrate/impact_times.h"

namespace bouncecal::calibrate {

// Synthetic bounce sequences whose restitution scatters from impact to impact, as real balls do
// (impact point, spin, surface), for measuring how often the confidence intervals cover the
// material's damping (tests/calibrate_coverage_test.cc, bench/calibrate_coverage_bench.cc).
// Flights are ballistic and contacts instantaneous: the flight after impact k lasts
// e_k times the one before it (the first one before it being the fall from drop_height_m), with
//   e_k = restitution (1 + recording_relative_offset z_r) (1 + relative_jitter z_k),
// z independent standard normals (z_r shared by the impacts of one recording), and every onset
// moved by timing_sigma_s z. Draws come from RandomStream(seed, recording, ...), so a recording
// is the same on every platform.
struct JitteredDropOptions {
  double drop_height_m = 0.2;
  double gravity_mps2 = 9.81;
  double restitution = 0.65;
  double relative_jitter = 0.03;
  double recording_relative_offset = 0;
  int impacts = 12;
  double timing_sigma_s = 20e-6;  // also stated as every onset's uncertainty
  double start_s = 0.5;           // when the ball is released (the first impact comes later)
  std::uint64_t seed = 1;
  std::uint64_t recording = 0;
};

// Throws ConfigError for an option outside its range (restitution in (0, 1), jitter and offset in
// [0, 0.2], impacts >= 2, timing sigma >= 0, positive height and gravity).
MeasuredSequence JitteredDrop(const JitteredDropOptions& options);

// The material's mean energy loss per impact, 1 - E[e_k^2] = 1 - e^2 (1 + j^2) (1 + b^2): what
// an average over many impacts and recordings of eta_k converges to.
double MaterialEnergyLoss(const JitteredDropOptions& options);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_JITTERED_DROP_H_
