#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_

#include <numeric>
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

}  // namespace bouncecal::audio::testing

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_SEQUENCE_TEST_SUPPORT_H_
