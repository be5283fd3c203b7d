#include "synth/limiter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <vector>

namespace bouncecal::audio {
namespace {

// The automatic gain control's gain per sample (linear): from gain_db, steered toward the target
// over the recent mean square at no more than slew_db_per_s, never above gain_db.
std::vector<double> AgcGains(const LimiterOptions& options, double sample_rate_hz,
                             std::span<const float> signal) {
  std::vector<double> gains(signal.size(), std::pow(10.0, options.gain_db / 20.0));
  if (!options.target_dbfs) return gains;
  const double smoothing = std::exp(-1.0 / (options.level_time_s * sample_rate_hz));
  const double step_db = options.slew_db_per_s / sample_rate_hz;
  double mean_square = 0;
  double gain_db = options.gain_db;
  for (std::size_t i = 0; i < signal.size(); ++i) {
    mean_square = smoothing * mean_square + (1 - smoothing) * signal[i] * signal[i];
    // The level the input has; the gain that would put it at the target (no level: the most).
    const double wanted_db =
        mean_square > 0
            ? std::min(options.gain_db, *options.target_dbfs - 10.0 * std::log10(mean_square))
            : options.gain_db;
    gain_db += std::clamp(wanted_db - gain_db, -step_db, step_db);
    gains[i] = std::pow(10.0, gain_db / 20.0);
  }
  return gains;
}

}  // namespace

void ApplyLimiter(const LimiterOptions& options, double sample_rate_hz, std::span<float> signal) {
  const std::vector<double> gains = AgcGains(options, sample_rate_hz, signal);
  const double ceiling = std::pow(10.0, options.ceiling_dbfs / 20.0);
  const auto lookahead = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(options.lookahead_s * sample_rate_hz)));
  const double attack = std::exp(-3.0 / static_cast<double>(lookahead));
  const double release = std::exp(-1.0 / (options.release_s * sample_rate_hz));
  const std::size_t n = signal.size();
  const auto magnitude = [&](std::size_t i) { return std::fabs(gains[i] * signal[i]); };
  // Indices of the window [i, i + lookahead) whose magnitudes decrease: its front is the loudest.
  std::deque<std::size_t> loudest;
  std::size_t pushed = 0;
  double limiter_gain = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    for (; pushed < std::min(n, i + lookahead); ++pushed) {
      while (!loudest.empty() && magnitude(loudest.back()) <= magnitude(pushed)) {
        loudest.pop_back();
      }
      loudest.push_back(pushed);
    }
    while (loudest.front() < i) loudest.pop_front();
    const double peak = magnitude(loudest.front());
    const double wanted = peak > ceiling ? ceiling / peak : 1.0;
    limiter_gain = wanted < limiter_gain ? attack * limiter_gain + (1 - attack) * wanted
                                         : release * limiter_gain + (1 - release) * wanted;
    const double out = gains[i] * signal[i];
    // The approach is exponential: where it has not reached the ceiling when the peak arrives,
    // that sample is held to it, as a limiter's final safety clip does.
    if (std::fabs(out) * limiter_gain > ceiling) limiter_gain = ceiling / std::fabs(out);
    signal[i] = static_cast<float>(out * limiter_gain);
  }
}

}  // namespace bouncecal::audio
