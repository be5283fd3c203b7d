#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_

#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// In a transform codec's file the event merger's choice between two sounds closer than
// min_gap_ms is unreliable: the codec moves energy across its block, so the later part of one
// impact's sound can out-level and out-rise its true start, which then loses the merge (the
// detector suite's knock_speech_before as AAC 128k and Opus 64k: a bounce 2.8 ms late; a Vorbis
// 64k drop of silent_wrong_sweep.py seed 101, #60: 3.9 ms late). A bounce sequence knows more than
// the merger: its neighbours' intervals. A member that won a merge over an earlier sound is
// compared with that sound by how well each continues the sequence's interval ratios (a line in ln
// ratio through the ratios neither moves); where the earlier one fits clearly better, it becomes
// the member's onset. Only members the response timing did not time (Impact::timed_from_response:
// an aligned onset is its own evidence) and left where the merger put them.
void TakeMergedOnsetsThatFitTheSequence(std::vector<Impact>& impacts,
                                        const std::vector<MergedEvent>& merged,
                                        const std::vector<BounceSequence>& sequences);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_
