#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_ANTI_ALIASING_FILTER_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_ANTI_ALIASING_FILTER_H_

#include <span>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {

// A filter's measured figures (see MeasureFilter).
struct FilterFigures {
  double passband_ripple_db = 0.0;
  double stopband_attenuation_db = 0.0;
};

// The decimation filter of a RecordingChain, at the high rate oversampling x fs.
//
// Linear phase: a Kaiser-windowed sinc (Kaiser 1974; Oppenheim & Schafer, "Discrete-Time Signal
// Processing", 3rd ed., 7.5-7.6): cutoff midway between the band edges, window
// beta = 0.1102 (A - 8.7) for A > 50 dB (0.5842 (A - 21)^0.4 + 0.07886 (A - 21) for 21-50 dB)
// taken for A + 0.5 dB, an odd length from Kaiser's estimate N = (A - 7.95) / (2.285 dw) + 1
// (dw the transition width in rad per high-rate sample), lengthened by 2 taps at a time until
// the measured stop band reaches A (+0.05 dB for the measuring grid); taps scaled to unit DC
// gain. The ripple is then about delta = 10^(-A/20) in both bands. With the default edges the
// cutoff is exactly fs / 2, so every oversampling-th tap from the centre is a zero of the sinc
// (a Nyquist filter): an impulse ON an output sample leaves the other output samples untouched,
// one between samples rings into its neighbours.
//
// Minimum phase: the same magnitude response with all zeros inside or on the unit circle, by
// the homomorphic (real-cepstrum) method (Oppenheim & Schafer ch. 13; Smith, "Spectral Audio
// Signal Processing", "Minimum-phase filter design"): log|H| on a grid of 64x the filter length,
// its cepstrum folded onto positive quefrencies, exponentiated back; the first N taps kept. |H|
// is floored 60 dB under delta before the logarithm (its stop-band zeros would give -inf); the
// length is chosen, as for the linear-phase filter, so that the minimum-phase taps themselves
// meet A.
struct AntiAliasingFilter {
  std::vector<double> taps;
  int oversampling = 1;
  // Output sample n reads high-rate samples n * oversampling + lead - k for tap k: lead is the
  // linear-phase filter's group delay (taps - 1) / 2, compensated (zero phase), and 0 for the
  // minimum-phase filter (causal: output n never sees input after its own time).
  int lead = 0;
  double kaiser_beta = 0.0;
  double cutoff_cycles_per_sample = 0.0;  // of the linear-phase prototype, at the high rate
  FilterFigures figures;                  // of these taps, measured by the design
};

// chain.oversampling, or when it is 0 (automatic) the smallest factor >= 8 that reaches 384 kHz.
int ResolvedOversampling(const RecordingChain& chain, double sample_rate_hz);

// Throws ConfigError (one line) for a chain ValidateSynthesisOptions would refuse, or one whose
// filter would be longer than 2^16 taps or miss its stop band (never seen for 40-150 dB).
AntiAliasingFilter DesignAntiAliasingFilter(const RecordingChain& chain, double sample_rate_hz);

// The linear-phase Kaiser design alone (odd length `taps`), unit DC gain.
std::vector<double> KaiserLowPass(int taps, double cutoff_cycles_per_sample, double beta);

// Kaiser's beta for a stop band of attenuation_db.
double KaiserBeta(double attenuation_db);

// The minimum-phase filter of the same length and magnitude response (see above).
std::vector<double> MinimumPhase(std::span<const double> linear_phase, double floor_magnitude);

// Largest |20 log10 |H(f)|| over [0, passband edge] and smallest -20 log10 |H(f)| over
// [stopband edge, high-rate Nyquist], from the edges themselves and an FFT of the taps
// zero-padded to >= 32 x their length (>= 32 points per 1/taps, a stop-band lobe's width).
FilterFigures MeasureFilter(std::span<const double> taps, int oversampling,
                            double passband_edge_fraction, double stopband_edge_fraction);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_ANTI_ALIASING_FILTER_H_
