#include "synth/limiter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>

namespace bouncecal::audio {
namespace {

// The automatic gain control, in place: a gain from gain_db, steered toward the target over the
// recent mean square at no more than slew_db_per_s and never above gain_db, or fixed there.
void ApplyAgcGain(const LimiterOptions& options, double sample_rate_hz, std::span<float> signal) {
  if (!options.target_dbfs) {
    const auto gain = static_cast<float>(std::pow(10.0, options.gain_db / 20.0));
    for (float& sample : signal) sample *= gain;
    return;
  }
  const double smoothing = std::exp(-1.0 / (options.level_time_s * sample_rate_hz));
  const double step_db = options.slew_db_per_s / sample_rate_hz;
  double mean_square = 0;
  double gain_db = options.gain_db;
  for (float& sample : signal) {
    mean_square = smoothing * mean_square + (1 - smoothing) * sample * sample;
    // The gain that would put the level at the target (no level yet: the most).
    const double wanted_db =
        mean_square > 0
            ? std::min(options.gain_db, *options.target_dbfs - 10.0 * std::log10(mean_square))
            : options.gain_db;
    gain_db += std::clamp(wanted_db - gain_db, -step_db, step_db);
    sample = static_cast<float>(sample * std::pow(10.0, gain_db / 20.0));
  }
}

}  // namespace

void ApplyLimiter(const LimiterOptions& options, double sample_rate_hz, std::span<float> signal) {
  ApplyAgcGain(options, sample_rate_hz, signal);
  const double ceiling = std::pow(10.0, options.ceiling_dbfs / 20.0);
  const auto lookahead = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(options.lookahead_s * sample_rate_hz)));
  const double attack = std::exp(-3.0 / static_cast<double>(lookahead));
  const double release = std::exp(-1.0 / (options.release_s * sample_rate_hz));
  const std::size_t n = signal.size();
  // Indices of the window [i, i + lookahead) whose magnitudes decrease: its front is the loudest.
  // Only samples from i on are compared, and those are not limited yet: the work is in place.
  std::deque<std::size_t> loudest;
  std::size_t pushed = 0;
  double limiter_gain = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    while (!loudest.empty() && loudest.front() < i) loudest.pop_front();
    for (; pushed < std::min(n, i + lookahead); ++pushed) {
      while (!loudest.empty() && std::fabs(signal[loudest.back()]) <= std::fabs(signal[pushed])) {
        loudest.pop_back();
      }
      loudest.push_back(pushed);
    }
    const double peak = std::fabs(signal[loudest.front()]);
    const double wanted = peak > ceiling ? ceiling / peak : 1.0;
    limiter_gain = wanted < limiter_gain ? attack * limiter_gain + (1 - attack) * wanted
                                         : release * limiter_gain + (1 - release) * wanted;
    const double out = signal[i];
    // The approach is exponential: where it has not reached the ceiling when the peak arrives,
    // that sample is held to it, as a limiter's final safety clip does.
    if (std::fabs(out) * limiter_gain > ceiling) limiter_gain = ceiling / std::fabs(out);
    signal[i] = static_cast<float>(out * limiter_gain);
  }
}

}  // namespace bouncecal::audio
