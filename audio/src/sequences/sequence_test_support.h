#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_

#include <numeric>
#include <tuple>
#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio::testing {

// Every impact, in order, as one bounce sequence (for the rules that run on found sequences).
inline std::vector<BounceSequence> OneSequence(const std::vector<Impact>& impacts) {
  BounceSequence sequence;
  sequence.impact_indices.resize(impacts.size());
  std::iota(sequence.impact_indices.begin(), sequence.impact_indices.end(), 0);
  return {sequence};
}

// Impacts as a detector gave them: onset s, sigma s, peak dBFS, residual-only (0 or 1).
inline std::vector<Impact> FromDetected(
    const std::vector<std::tuple<double, double, double, int>>& detected) {
  std::vector<Impact> impacts;
  for (const auto& [onset_s, sigma_s, peak_dbfs, residual_only] : detected) {
    impacts.push_back({.onset_s = onset_s,
                       .onset_uncertainty_s = sigma_s,
                       .peak_dbfs = peak_dbfs,
                       .residual_only = residual_only != 0});
  }
  return impacts;
}

}  // namespace bouncecal::audio::testing

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_
