#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_NOISE_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_NOISE_H_

#include <span>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/random_stream.h"

namespace bouncecal::audio {

// Adds zero-mean Gaussian noise of the given colour to signal; the realisation's mean square
// over signal is exactly target_rms^2 (it is rescaled, so a requested SNR holds to rounding).
// Pink noise is white noise through Paul Kellett's "refined" 1/f filter (within 0.05 dB of
// -3 dB/octave above 9 Hz at 44.1 kHz). The stream is run twice (measure, then add), so memory
// stays at the signal itself even for hour-long files.
void AddNoise(NoiseColor color, double target_rms, const RandomStream& random,
              std::span<float> signal);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_NOISE_H_
