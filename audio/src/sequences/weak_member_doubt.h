#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_WEAK_MEMBER_DOUBT_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_WEAK_MEMBER_DOUBT_H_

#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// A residual-only member of a bounce sequence (Impact::residual_only) is weak evidence: a rise in
// the ringing of earlier bounces, whose onset may belong to the bounce or to a later swell of the
// tail. The sequence's own earlier flights predict where the bounce is: t_{k-1} + r dt_{k-1},
// r the mean of the last three interval ratios. Where a residual-only member misses that by more
// than kDoubtSigmas of what the prediction (a ball's scatter of e: 3 % pooled with the spread of
// the sequence's own ratios so far; the earlier members' timing) and its own stated sigma explain
// together, one of the two is wrong and nothing tells which; half
// the distance is added to its sigma in quadrature, as where the detector's onset and the
// response alignment disagree (response_timing.cc). Members are taken in order, so a widened
// member's sigma widens the next prediction. Onsets are not moved.
void StateDoubtOfWeakMembers(std::vector<Impact>& impacts,
                             const std::vector<BounceSequence>& sequences);

// A member whose onset search an earlier, still-rising candidate cut (Impact::unsearched_span_s)
// may have begun anywhere from that search's start: its uncertainty is at least that span's half.
// Only for members the response timing did not time (an aligned onset is its own evidence), and
// only here, after the sequences are found: in the detector's sigma it changed which impact the
// response timing takes for its template, and a precursor drop's members then switched between
// their clicks and bounces (silent_wrong_sweep.py --precursors seed 8 #165: eta-bar 39 sigmas off).
void StateUnsearchedOnsetSpans(std::vector<Impact>& impacts,
                               const std::vector<BounceSequence>& sequences);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_WEAK_MEMBER_DOUBT_H_
