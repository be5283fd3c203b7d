#include "detector/later_attack.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace bouncecal::audio {
namespace {

// The onset's own sound: the first millisecond after it (a hard contact's first lobes and the
// plate's first periods; a codec's sample-level smearing stays inside it).
constexpr double kEarlyWindowS = 1e-3;
// The early part this far below the peak is no attack: the detector's rise threshold, by which
// an impact stands out of what precedes it.
constexpr double kQuietBelowPeakDb = 10.0;
// Where the attack begins: the first sample within this of the peak.
constexpr double kAttackBelowPeakDb = 6.0;

}  // namespace

double LaterAttackS(std::span<const float> after_onset, int sample_rate_hz) {
  if (after_onset.empty() || sample_rate_hz <= 0) return 0;
  const auto early = std::min<std::size_t>(
      after_onset.size(), static_cast<std::size_t>(std::ceil(kEarlyWindowS * sample_rate_hz)));
  double peak = 0, early_peak = 0;
  for (std::size_t i = 0; i < after_onset.size(); ++i) {
    const double magnitude = std::fabs(after_onset[i]);
    peak = std::max(peak, magnitude);
    if (i < early) early_peak = std::max(early_peak, magnitude);
  }
  if (!(peak > 0) || early_peak >= peak * std::pow(10.0, -kQuietBelowPeakDb / 20)) return 0;
  const double attack = peak * std::pow(10.0, -kAttackBelowPeakDb / 20);
  for (std::size_t i = early; i < after_onset.size(); ++i) {
    if (std::fabs(after_onset[i]) >= attack) return static_cast<double>(i) / sample_rate_hz;
  }
  return 0;
}

}  // namespace bouncecal::audio
