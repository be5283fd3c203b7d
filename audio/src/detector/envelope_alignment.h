#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_ENVELOPE_ALIGNMENT_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_ENVELOPE_ALIGNMENT_H_

#include <cstdint>
#include <span>
#include <vector>

namespace bouncecal::audio {

// Relative timing of an impact from the energy envelopes of its response in a few octave bands,
// for the impacts whose waveform does not align with the template's (response_timing.h).
//
// Why: the impacts of a real ball (ping-pong, tennis ball, basketball) excite the same modes in a
// different mix and phase from one spot of its surface to the next, so their waveforms correlate
// at rho 0.2-0.5 and the waveform alignment leaves them to the detector's first lobe, which a
// transform codec's pre-echo moves by 1-4 ms in some copies. The energy in a band rises at the
// start of contact and decays with the band's modes whatever their phases, so envelopes
// correlate where waveforms do not, and the pre-echo before the attack holds a small part of an
// envelope's energy (the quantisation noise of a frame, spread over it) where it can move a
// first lobe's pick by the whole frame.
//
// Each band (octaves from 250 Hz up to 16 kHz or 0.45 of the rate) is filtered with a causal
// band-pass (the same filter for every impact, so its delay cancels), squared, box-smoothed over
// half a period of the band's lowest frequency (the square's ripple) and decimated to about 12
// kHz; the template's envelopes from 1 ms before its onset to the end of its response are
// correlated (Pearson, so the level does not matter) with the target's at every lag within the
// search, in each band the template holds at least 1 % of its strongest band's energy (a codec
// drops the bands it cannot afford). The bands' mean correlation gives the lag (a parabola
// through its peak).
//
// Its uncertainty is the alignment's own: time-delay estimation from the mean correlation (its
// curvature sets the correlation time T, the compared envelope holds about length / T
// independent values, and the residual 1 - rho^2 spreads over them) and the standard error of
// the bands' own peaks inside the mean's lobe (a different mix of modes moves each band's
// envelope differently), in quadrature, at least one decimated step (83 us at 48 kHz). It is
// unusable, and the impact keeps its onset as before, where it is ambiguous: a mean correlation
// under min_correlation (real balls' bounces read 0.52-0.9 against their recording's template,
// other sounds 0.0-0.4), another lag within min_peak_margin of it beyond a dip the bands resolve
// (the mean rising out of it by more than the bands' standard error of that rise: a wiggle on
// the peak's own flank is no rival), a peak at the edge of the search, or fewer than min_bands
// bands with a peak of their own in the mean's lobe. A band whose best lag lies elsewhere does
// not veto: one band's envelope can hold two bumps (a room echo, two modes beating; ub-mth337
// pingpong.wav's 1-2 kHz band peaks 2.7 ms late at every bounce), which the other bands resolve.
struct EnvelopeAlignmentOptions {
  double pre_s = 1e-3;           // envelope compared before the onset
  double min_correlation = 0.5;  // the bands' mean at the peak
  double min_peak_margin = 0.15;
  double band_correlation = 0.5;  // a band correlating at least this well votes
  int min_bands = 3;
};

struct EnvelopeAlignment {
  bool usable = false;
  double lag_samples = 0;  // the target's response starts this many samples after its onset
  double sigma_samples = 0;
  double correlation = 0;
  int bands = 0;  // bands that voted
};

// One second-order section's coefficients, normalised by a0.
struct BandPassSection {
  double b0 = 0, b2 = 0, a1 = 0, a2 = 0;
};

class EnvelopeAligner {
 public:
  // Octave bands from 250 Hz to 16 kHz; fewer where 0.45 of the rate is lower.
  static constexpr std::size_t kMaxBands = 6;

  // templ: the template's window (samples, not differences), its onset at index lead. search:
  // the largest lag tried after the onset; before it, at most lead minus pre_s (the envelope
  // compared before the onset must lie in the window). Windows hold search samples more after
  // the onset than any response compared.
  EnvelopeAligner(int sample_rate_hz, std::span<const float> templ, std::int64_t lead,
                  std::int64_t search, const EnvelopeAlignmentOptions& options = {});

  // target: a window of the same layout; n: the response compared (at most the template's).
  EnvelopeAlignment Align(std::span<const float> target, std::int64_t n) const;

 private:
  struct Band {
    double low_hz = 0;
    double high_hz = 0;
    BandPassSection filter;
    std::vector<float> templ;  // the template's decimated envelope, whole window
  };
  std::vector<std::vector<float>> Envelopes(std::span<const float> window) const;
  EnvelopeAlignmentOptions options_;
  int sample_rate_hz_ = 0;
  std::int64_t step_ = 1;    // decimation
  std::int64_t lead_ = 0;    // decimated
  std::int64_t pre_ = 0;     // decimated
  std::int64_t before_ = 0;  // lags tried before the onset, decimated
  std::int64_t after_ = 0;   // and after it
  std::vector<Band> bands_;
  std::vector<bool> used_;  // bands with enough of the template's energy
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_ENVELOPE_ALIGNMENT_H_
