#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_

#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// The event merger's choice between two sounds closer than min_gap_ms is not always the bounce.
// In a transform codec's file the codec moves energy across its block, so the later part of one
// impact's sound can out-level and out-rise its true start, which then loses the merge (the
// detector suite's knock_speech_before as AAC 128k and Opus 64k: a bounce 2.8 ms late; a Vorbis
// 64k drop of silent_wrong_sweep.py seed 101, #60: 3.9 ms late). In any file a precursor 10-12 dB
// under its bounce rings into it and keeps one candidate open, so the candidate's onset is the
// precursor's and the bounce is merged as the rest of its sound, or the two are kept apart and the
// bounce wins: which one is timed changes from bounce to bounce with their levels (seed 53 #115, a
// 22 kHz WAV: four members on their precursors, the fifth on its bounce 5.9 ms later at +-65 us,
// eta-bar 0.4359 +- 0.0002 against 0.4480). A bounce sequence knows more than the merger: its
// neighbours' intervals. A member is compared with each sound merged into it between its
// neighbours, earlier or later (the last member: earlier only), by how well each continues the
// sequence's interval ratios (a line in ln ratio through the ratios neither moves); where another
// fits clearly better, it becomes the member's onset. What the sequence calls the bounce is then
// the sound its members share, a precursor at a constant lead as good as the bounce for the
// intervals. Only members the response timing did not time (Impact::timed_from_response: an aligned
// onset is its own evidence) and left where the merger put them. The taken sound's entry in
// `merged` then records the onset the merger kept, as the sound set aside. A band-detected member
// that keeps its onset over an earlier sound it out-levelled by less than a rise threshold, which
// the ratios do not clearly reject either, states half their distance: the two may be one slowly
// rising sound.
//
// Before that, each sequence is weighed whole where three or more of its members show another
// sound at one spacing (2 ms or more), merged into them or their own later, louder sound
// (Impact::later_onset_s): pairs such as a click and its bounce, some members timed on one sound
// and some on the other, each interval across a switch off by the spacing. The members move to
// one sound of their pairs where that fits the ratios clearly better, timed-from-response members
// too (a run of consecutive members only where its ends fit better moved), and a first or last
// member whose sound is not known then states half the spacing, as does one inside the sequence
// whose own move by the spacing the ratios clearly prefer, to a run's on either side of it.
void TakeMergedOnsetsThatFitTheSequence(std::vector<Impact>& impacts,
                                        std::vector<MergedEvent>& merged,
                                        const std::vector<BounceSequence>& sequences);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_MERGED_ALTERNATIVES_H_
