#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_

#include <optional>
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

// Where that later sound itself begins (s after the onset), in any file: its start of contact is
// picked as an impact's is (onset_picker.h), on the samples from the end of the onset's own first
// millisecond up to the later sound's peak. A click 9-14 dB under its bounce and a few ms ahead
// of it rings into the bounce and keeps one candidate, whose onset is then the click's, with
// nothing recorded of the bounce (silent_wrong_sweep.py --precursors): this is that bounce's
// onset, an alternative a bounce sequence may take (merged_alternatives.h). Nothing unless the
// first millisecond stays 6 dB (not 10) under the later peak: such clicks vary by a few dB from
// bounce to bounce. (Placing the later sound by its timing reference against the onset's own, as
// the detector states onsets, moved it by -1.0 to +0.1 ms on the sweep's drops and left seed 7
// #63 wrong; a 0.8 ms contact's later sound is picked about 0.5 ms late either way.)
std::optional<double> LaterSoundOnsetS(std::span<const float> after_onset, int sample_rate_hz);

// How far the loudest sample of `after_onset` stands above the loudest of its first millisecond
// (dB): 0 where the onset's own sound is the loudest, +infinity after a silent first millisecond.
double PeakOverFirstMillisecondDb(std::span<const float> after_onset, int sample_rate_hz);

// The sharpest rise of level after the onset's first 2 ms: where the energy of the next 0.5 ms
// stands furthest above that of the 2 ms before it. A phone's look-ahead limiter holds a drop's
// loud sounds at one ceiling, so a bounce after its click no longer out-levels the click's first
// millisecond (LaterSoundOnsetS finds nothing), but it still begins with a fresh attack out of
// the click's ringing, which the limiter, turning its gain down for the attack's peak, lowers
// with it. Energy, not peak, over the 2 ms before: a plate's beating modes swing the peak of
// every quarter millisecond by 5-10 dB (the limited sweep files' ringing at 96 kHz).
struct LaterRise {
  double after_onset_s = 0;  // where the 0.5 ms that rose begins
  double rise_db = 0;        // its mean power over that of the 2 ms before, dB
};
std::optional<LaterRise> SharpestLaterRise(std::span<const float> after_onset, int sample_rate_hz);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_LATER_ATTACK_H_
