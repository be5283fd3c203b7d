#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_

#include <cstddef>
#include <vector>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// A knock, a thump, speech or the release before a drop can land where a bounce before the
// first would be, and a chain of bounces then starts at it: its first ratio, and so its eta-bar,
// is wrong at exit 0 (bench/knock_sweep.py). These judge a chain's first members (indices into
// `impacts`, in time order) against what its later bounces show, and return how many of them
// are such sounds; the chain starts after them.

// By timing: a leading ratio far off the line through the next 4-6 ratios.
std::size_t LeadingSoundsBeforeTheDrop(const std::vector<Impact>& impacts,
                                       const std::vector<int>& members);

// By timing too, but choosing: a chain's first member is the loudest of the sounds that could start
// it (ChainFinder::Better breaks ties by loudness), and an impact's echo 12-30 ms after it (beyond
// the detector's merge gap) can be the louder. Where the first ratio misses the line through the
// next 4-6 ratios by more than 3 sigmas and another free band-detected sound within 30 ms of the
// first member gives a first ratio within 2 sigmas of it, the best fitting such sound is the first
// member. Returns the index into `impacts` of the member that starts the chain (members[0] where
// none fits better). Why: pingpong_table of the detector suite as AAC 128k started its sequence at
// a room reflection 15.7 ms after the first bounce, 1.5 dB louder than it (e_1 0.8925 against
// 0.8616, eta-bar 0.0181 off at 6 sigmas, exit 0).
int FirstMemberThatFitsTheDrop(const std::vector<Impact>& impacts, const std::vector<bool>& free,
                               const std::vector<int>& members);

// By level: a leading member much quieter than the next, where a bounce before it would have hit
// faster and so sounded louder. Never leaves fewer than `fewest_left` members.
std::size_t LeadingSoundsQuieterThanTheDrop(const std::vector<Impact>& impacts,
                                            const std::vector<int>& members,
                                            std::size_t fewest_left);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_
