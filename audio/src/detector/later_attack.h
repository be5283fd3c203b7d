#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_

#include <span>

namespace bouncecal::audio {

// How long after a detected onset the impact's attack may really begin, in a transform codec's
// file (AAC, MP3, Vorbis, Opus). The codec spreads the quantisation noise of a loud attack over
// the block before it (pre-echo: up to a short block, 2.7-8 ms at 48-16 kHz, or a whole frame
// where the encoder keeps its long block), and where that noise rises into the attack without a
// break the detector's onset is the noise's start, milliseconds early, with no merged event to
// show it. A hard contact's own sound is near its peak at once; pre-echo is well below the attack
// it precedes. So where the first kEarlyWindowS after the onset stay kQuietBelowPeakDb or more
// below the loudest sample of `after_onset` (the samples from the onset on, up to where the next
// impact could begin), the attack may begin where the signal first comes within 6 dB of that
// peak: that distance is returned (s), else 0. (A soft contact that builds up over milliseconds
// reads the same; its first lobe is then no more certain under a codec.)
double LaterAttackS(std::span<const float> after_onset, int sample_rate_hz);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_
