#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_BAND_LIMIT_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_BAND_LIMIT_H_

#include <span>

namespace bouncecal::audio {

// Low-passes signal in place at cutoff_hz with a zero-phase (symmetric, uncompensated-delay-
// free) Blackman-windowed sinc FIR whose transition band is transition_hz wide (about -74 dB
// stop band; Oppenheim & Schafer, "Discrete-Time Signal Processing", 7.5). This is what a
// lossy codec or a band-limited phone path does to a recording (Palla-audio: nothing above
// 6-7 kHz; the YouTube extracts: nothing above 16 kHz). Being zero-phase, it rings symmetrically
// and so spreads a little energy BEFORE every onset ("pre-echo"), as such codecs do.
void BandLimit(double cutoff_hz, double transition_hz, double sample_rate_hz,
               std::span<float> signal);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_BAND_LIMIT_H_
