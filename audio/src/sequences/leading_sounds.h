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

// By level: a leading member much quieter than the next, where a bounce before it would have hit
// faster and so sounded louder. Never leaves fewer than `fewest_left` members.
std::size_t LeadingSoundsQuieterThanTheDrop(const std::vector<Impact>& impacts,
                                            const std::vector<int>& members,
                                            std::size_t fewest_left);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_
