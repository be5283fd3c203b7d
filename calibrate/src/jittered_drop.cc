#include "bouncecal/calibrate/jittered_drop.h"

#include <cmath>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/random_stream.h"

namespace bouncecal::calibrate {
namespace {

void Validate(const JitteredDropOptions& options) {
  const auto fail = [](const std::string& what) { throw ConfigError("jittered drop: " + what); };
  if (!(options.drop_height_m > 0) || !std::isfinite(options.drop_height_m))
    fail("drop_height_m must be a positive number of metres");
  if (!(options.gravity_mps2 > 0) || !std::isfinite(options.gravity_mps2))
    fail("gravity_mps2 must be positive");
  if (!(options.restitution > 0 && options.restitution < 1))
    fail("restitution must be in (0, 1), got " + std::to_string(options.restitution));
  if (!(options.relative_jitter >= 0 && options.relative_jitter <= 0.2) ||
      !(options.recording_relative_offset >= 0 && options.recording_relative_offset <= 0.2))
    fail("relative_jitter and recording_relative_offset must be in [0, 0.2]");
  if (options.impacts < 2) fail("impacts must be at least 2");
  if (!(options.timing_sigma_s >= 0) || !std::isfinite(options.timing_sigma_s))
    fail("timing_sigma_s must be >= 0");
}

}  // namespace

MeasuredSequence JitteredDrop(const JitteredDropOptions& options) {
  Validate(options);
  RandomStream restitution_draws(options.seed, options.recording, 0);
  RandomStream timing_draws(options.seed, options.recording, 1);
  const double g = options.gravity_mps2;
  const double fall = std::sqrt(2 * options.drop_height_m / g);
  const double recording_factor =
      1 + options.recording_relative_offset * restitution_draws.Gaussian();
  MeasuredSequence sequence;
  sequence.source = "jittered#" + std::to_string(options.recording + 1);
  double onset = options.start_s + fall;
  double flight = 2 * fall;  // the flight that would have preceded the first impact
  for (int k = 0; k < options.impacts; ++k) {
    const double noise = options.timing_sigma_s * timing_draws.Gaussian();
    sequence.impacts.push_back({onset + noise, options.timing_sigma_s});
    // Capped below 1: a jitter draw beyond 1 / e - 1 would make the ball gain energy.
    const double e = std::min(options.restitution * recording_factor *
                                  (1 + options.relative_jitter * restitution_draws.Gaussian()),
                              0.999);
    flight *= e;
    onset += flight;
  }
  return sequence;
}

double MaterialEnergyLoss(const JitteredDropOptions& options) {
  const double e = options.restitution;
  return 1 - e * e * (1 + std::pow(options.relative_jitter, 2)) *
                 (1 + std::pow(options.recording_relative_offset, 2));
}

}  // namespace bouncecal::calibrate
