#include "plot/min_max_decimator.h"

#include <algorithm>
#include <limits>

#include "bouncecal/error.h"

namespace bouncecal::apps {

MinMaxDecimator::MinMaxDecimator(std::int64_t expected_samples, int columns, int sample_rate_hz)
    : expected_samples_(std::max<std::int64_t>(expected_samples, 1)),
      sample_rate_hz_(sample_rate_hz) {
  if (columns < 1) throw ConfigError("a waveform plot needs at least 1 column");
  if (sample_rate_hz < 1) throw ConfigError("a waveform plot needs a positive sample rate");
  const auto count = static_cast<std::size_t>(columns);
  min_.assign(count, std::numeric_limits<float>::infinity());
  max_.assign(count, -std::numeric_limits<float>::infinity());
  first_.assign(count, -1);
  last_.assign(count, -1);
}

void MinMaxDecimator::Add(std::span<const float> samples) {
  const auto columns = static_cast<std::int64_t>(min_.size());
  for (float sample : samples) {
    const std::int64_t column = std::min(seen_ * columns / expected_samples_, columns - 1);
    const auto c = static_cast<std::size_t>(column);
    min_[c] = std::min(min_[c], sample);
    max_[c] = std::max(max_[c], sample);
    if (first_[c] < 0) first_[c] = seen_;
    last_[c] = seen_;
    ++seen_;
  }
}

WaveformColumns MinMaxDecimator::Finish() const {
  WaveformColumns result;
  for (std::size_t c = 0; c < min_.size(); ++c) {
    if (first_[c] < 0) continue;
    result.time_s.push_back(0.5 * static_cast<double>(first_[c] + last_[c]) / sample_rate_hz_);
    result.min.push_back(min_[c]);
    result.max.push_back(max_[c]);
  }
  return result;
}

}  // namespace bouncecal::apps
