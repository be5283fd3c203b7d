#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_DETECTOR_FRAMES_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_DETECTOR_FRAMES_H_

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// Rises of this fraction of rise_threshold_db open a candidate (CandidateTracker); it counts as an
// impact only if it or a member of its min-gap group reaches the full threshold (EventMerger).
inline constexpr double kSecondaryRiseFraction = 0.5;

// The time grid every detector stage shares: energy frames of options.frame_ms and the windows,
// in frames, that the rise test and the candidate tracker read. Frame n covers samples
// [n hop, (n + 1) hop).
struct DetectorFrames {
  // The rise is measured against frames at least this far back, so the first frames of a rise
  // do not serve as their own reference.
  static constexpr double kRiseSkipMs = 0.5;
  // How long an impact may take to build up its rise: soft contacts (tennis, rubber) take a
  // millisecond or two.
  static constexpr double kAttackMs = 2.0;
  // After the first rising frame, the envelope peak of the impact is searched this long.
  static constexpr double kPeakSearchMs = 3.0;
  // A candidate that keeps rising is closed after min_gap_ms, at most this long.
  static constexpr double kMaxOpenMs = 50.0;
  static_assert(kPeakSearchMs > kAttackMs);

  DetectorFrames(int sample_rate_hz, const DetectorOptions& options)
      : rate_hz(sample_rate_hz),
        hop(std::max<std::int64_t>(1, std::llround(options.frame_ms * 1e-3 * sample_rate_hz))),
        frame_s(static_cast<double>(hop) / sample_rate_hz),
        lookback(Frames(options.rise_lookback_ms)),
        skip(std::max<std::int64_t>(1, Frames(kRiseSkipMs))),
        attack(Frames(kAttackMs)),
        peak(std::max(attack + 1, Frames(kPeakSearchMs))),
        max_open(std::max(peak, Frames(std::min(options.min_gap_ms, kMaxOpenMs)))) {}

  std::int64_t Samples(double seconds) const {
    return static_cast<std::int64_t>(std::ceil(seconds * rate_hz));
  }
  std::int64_t Frames(double ms) const {
    return std::max<std::int64_t>(1, std::llround(ms * 1e-3 * rate_hz / static_cast<double>(hop)));
  }

  int rate_hz;
  std::int64_t hop;       // samples per frame
  double frame_s;         // hop in seconds
  std::int64_t lookback;  // rise_lookback_ms
  std::int64_t skip;      // kRiseSkipMs
  std::int64_t attack;    // kAttackMs
  std::int64_t peak;      // kPeakSearchMs
  std::int64_t max_open;  // min(min_gap_ms, kMaxOpenMs)
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_DETECTOR_FRAMES_H_
