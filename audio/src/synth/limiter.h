#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_LIMITER_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_LIMITER_H_

#include <span>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {

// A phone's or a recorder's digital gain stage, in place: an automatic gain control's gain (where
// it stood in the quiet before the drop, then, with a target, steered toward it at a limited
// rate), then a look-ahead peak limiter at the ceiling, the stage an AGC ends with (WebRTC's, which
// browsers and many phone apps use, does). The limiter's gain is the ceiling over the loudest
// sample of the next lookahead_s, approached with a time constant of a third of the look-ahead (so
// it is reached by the time that sample arrives) and released exponentially over release_s; no
// sample leaves above the ceiling. What it does to a drop: the first, loudest bounces are brought
// down to the ceiling while the sounds just before them (a click 10 dB under a bounce, the previous
// bounce's ringing) are brought down less or not at all, so the level differences the detector
// weighs shrink, and the gain's dip starts up to the look-ahead before each limited bounce.
void ApplyLimiter(const LimiterOptions& options, double sample_rate_hz, std::span<float> signal);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_LIMITER_H_
