#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_REVERB_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_REVERB_H_

#include <span>
#include <vector>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/random_stream.h"

namespace bouncecal::audio {

// The diffuse part of a room impulse response in Schroeder's statistical model: Gaussian noise
// under an exponential envelope falling 60 dB in rt60_s, starting predelay_s after the direct
// sound, cut 90 dB down (1.5 rt60), scaled so that its energy is direct_to_reverberant_db below
// the unit direct impulse. Index 0 is the direct sound's arrival (the direct path itself is not
// included).
std::vector<double> DiffuseTail(const ReverbOptions& options, double sample_rate_hz,
                                RandomStream random);

// Adds signal convolved with tail to signal (FFT overlap-add through FFTW, memory bounded by
// the tail length, not the signal length). Output samples before the first non-zero input
// sample plus the tail's leading zeros are left untouched: the convolution is exactly zero there
// and FFT rounding must not put noise-like residue before the first onset.
void AddConvolution(std::span<const double> tail, std::span<float> signal);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_REVERB_H_
