#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_TENTATIVE_EXTENSION_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_TENTATIVE_EXTENSION_H_

#include <optional>
#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// ExtendSequencesWithTentative's result, with the grouping it made of the impacts it was given
// where it adopted none: its result is then those impacts, so that grouping is
// FindBounceSequences of the result, and GroupBounces need not search the same impacts twice
// (the search was 12 % of analysing analyze_bench's 10-minute WAV, half of it the second search).
struct TentativeExtension {
  std::vector<Impact> impacts;
  std::optional<SequenceResult> grouping;  // where nothing was adopted
};

TentativeExtension ExtendWithTentative(const std::vector<Impact>& impacts,
                                       const std::vector<Impact>& tentative,
                                       const SequenceOptions& options);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_TENTATIVE_EXTENSION_H_
