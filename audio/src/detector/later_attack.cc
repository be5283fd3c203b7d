#include "detector/later_attack.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "detector/onset_picker.h"

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
// A later sound is offered as an alternative onset where the first millisecond stays this far
// under it: a click 9-14 dB under its bounce varies by a few dB from bounce to bounce, and a
// bounce sequence takes the alternative only where its members switch between the two sounds of
// such pairs (merged_alternatives.h), so a lower bar costs nothing where they do not.
constexpr double kLaterSoundBelowPeakDb = 6.0;

// The loudest sample magnitude of the samples after an onset and of their first kEarlyWindowS,
// and how many samples that first part holds.
struct Peaks {
  double peak = 0;
  double early_peak = 0;
  std::size_t early = 0;
};

Peaks PeaksAfter(std::span<const float> after_onset, int sample_rate_hz) {
  Peaks peaks;
  peaks.early = std::min<std::size_t>(
      after_onset.size(), static_cast<std::size_t>(std::ceil(kEarlyWindowS * sample_rate_hz)));
  for (std::size_t i = 0; i < after_onset.size(); ++i) {
    const double magnitude = std::fabs(after_onset[i]);
    peaks.peak = std::max(peaks.peak, magnitude);
    if (i < peaks.early) peaks.early_peak = std::max(peaks.early_peak, magnitude);
  }
  return peaks;
}

// The first milliseconds of an impact at least `quiet_below_peak_db` under its loudest sample:
// where the signal first comes within kAttackBelowPeakDb of that peak (s), else 0.
double AttackAfterQuietStart(std::span<const float> after_onset, int sample_rate_hz,
                             double quiet_below_peak_db) {
  if (after_onset.empty() || sample_rate_hz <= 0) return 0;
  const auto [peak, early_peak, early] = PeaksAfter(after_onset, sample_rate_hz);
  if (!(peak > 0) || early_peak >= peak * std::pow(10.0, -quiet_below_peak_db / 20)) return 0;
  const double attack = peak * std::pow(10.0, -kAttackBelowPeakDb / 20);
  for (std::size_t i = early; i < after_onset.size(); ++i) {
    if (std::fabs(after_onset[i]) >= attack) return static_cast<double>(i) / sample_rate_hz;
  }
  return 0;
}

}  // namespace

double LaterAttackS(std::span<const float> after_onset, int sample_rate_hz) {
  return AttackAfterQuietStart(after_onset, sample_rate_hz, kQuietBelowPeakDb);
}

std::optional<double> LaterSoundOnsetS(std::span<const float> after_onset, int sample_rate_hz) {
  if (!(AttackAfterQuietStart(after_onset, sample_rate_hz, kLaterSoundBelowPeakDb) > 0)) {
    return std::nullopt;
  }
  const auto early = std::min<std::size_t>(
      after_onset.size(), static_cast<std::size_t>(std::ceil(kEarlyWindowS * sample_rate_hz)));
  // The window ends at the loudest sample, not at the first within 6 dB of it: the earlier sound's
  // own ringing can swell that close before the later sound begins, and the largest change of
  // level before the peak is where the later sound starts.
  std::size_t peak = 0;
  for (std::size_t i = 0; i < after_onset.size(); ++i) {
    if (std::fabs(after_onset[i]) > std::fabs(after_onset[peak])) peak = i;
  }
  if (peak <= early + 8) return std::nullopt;
  // What came before the later sound (the earlier one's ringing) is the picker's noise.
  const std::span<const float> window = after_onset.subspan(early, peak + 1 - early);
  const OnsetPick pick = PickOnset(window, 0, window.size() - 1);
  return (static_cast<double>(early) + pick.index) / sample_rate_hz;
}

std::optional<LaterRise> SharpestLaterRise(std::span<const float> after_onset, int sample_rate_hz) {
  if (sample_rate_hz <= 0) return std::nullopt;
  // The rise is looked for from where another sound of a pair may begin (pairs lie at least 2 ms
  // apart, merged_alternatives.cc), so the 2 ms before it are the onset's own sound.
  const auto before = static_cast<std::size_t>(std::ceil(2e-3 * sample_rate_hz));
  const auto rising =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(0.5e-3 * sample_rate_hz)));
  if (after_onset.size() < before + rising) return std::nullopt;
  std::vector<double> energy(after_onset.size() + 1, 0.0);  // running sum of squares
  for (std::size_t i = 0; i < after_onset.size(); ++i) {
    energy[i + 1] = energy[i] + static_cast<double>(after_onset[i]) * after_onset[i];
  }
  // Differences of the running sum carry its rounding: 100 dB under the window's mean power is
  // taken as no sound at all, so digital silence after a sound shows no rise of rounding noise.
  const double floor = 1e-10 * energy.back() / static_cast<double>(after_onset.size());
  std::optional<LaterRise> sharpest;
  double best_ratio = 0;
  for (std::size_t at = before; at + rising <= after_onset.size(); ++at) {
    const double earlier = (energy[at] - energy[at - before]) / static_cast<double>(before);
    const double later = (energy[at + rising] - energy[at]) / static_cast<double>(rising);
    if (!(earlier > floor) || !(later > best_ratio * earlier)) continue;
    best_ratio = later / earlier;
    sharpest = LaterRise{static_cast<double>(at) / sample_rate_hz, 10.0 * std::log10(best_ratio)};
  }
  return sharpest;
}

double PeakOverFirstMillisecondDb(std::span<const float> after_onset, int sample_rate_hz) {
  if (after_onset.empty() || sample_rate_hz <= 0) return 0;
  const Peaks peaks = PeaksAfter(after_onset, sample_rate_hz);
  if (!(peaks.peak > 0)) return 0;
  if (!(peaks.early_peak > 0)) return std::numeric_limits<double>::infinity();
  return 20.0 * std::log10(peaks.peak / peaks.early_peak);
}

}  // namespace bouncecal::audio
