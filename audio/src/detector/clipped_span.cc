#include "detector/clipped_span.h"

#include <algorithm>
#include <cmath>

namespace bouncecal::audio {
namespace {

bool Clipped(const SampleHistory<float>& raw, std::int64_t i) {
  const float x = raw[i];
  if (!(std::fabs(x) >= kClippedLevel)) return false;
  return (i > raw.begin() && raw[i - 1] == x) || (i + 1 < raw.end() && raw[i + 1] == x);
}

}  // namespace

std::int64_t ClippedSamplesBefore(const SampleHistory<float>& raw, std::int64_t onset,
                                  std::int64_t bridge, std::int64_t reach) {
  onset = std::min(onset, raw.end());
  const std::int64_t earliest = std::max(raw.begin(), onset - reach);
  std::int64_t start = onset;  // of the clipped stretch found so far
  for (std::int64_t i = onset - 1; i >= earliest && start - i <= bridge + 1; --i) {
    if (Clipped(raw, i)) start = i;
  }
  return onset - start;
}

std::int64_t ClippedLobeAfter(const SampleHistory<float>& raw, std::int64_t onset,
                              std::int64_t horizon, float min_lobe) {
  const std::int64_t begin = std::max(onset, raw.begin());
  const std::int64_t end = std::min(onset + horizon, raw.end());
  bool positive = false, negative = false;
  for (std::int64_t i = begin; i < end; ++i) {
    if (Clipped(raw, i)) {
      // The clipped lobe's own sign does not count: only lobes before it.
      const bool clipped_positive = raw[i] > 0;
      return (clipped_positive ? negative : positive) ? i - onset : 0;
    }
    positive = positive || raw[i] >= min_lobe;
    negative = negative || raw[i] <= -min_lobe;
  }
  return 0;
}

}  // namespace bouncecal::audio
