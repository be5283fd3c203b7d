#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_PICKER_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_PICKER_H_

#include <cstddef>
#include <limits>
#include <optional>
#include <span>

namespace bouncecal::audio {

struct OnsetPick {
  double index = 0;          // start of contact: fractional sample index into the window
  double sigma_samples = 0;  // one-sigma uncertainty
  // The impact's timing reference (see ReferenceCrossing) and its one-sigma uncertainty; NaN
  // where PickOnset could not place it.
  double reference_index = std::numeric_limits<double>::quiet_NaN();
  double reference_sigma_samples = std::numeric_limits<double>::quiet_NaN();
  // The level at which the reference was taken (see ReferenceCrossing); NaN where none was.
  double reference_level = std::numeric_limits<double>::quiet_NaN();
  // The fitted edge y = edge_amplitude (i - index)^edge_power; NaN where no edge was fitted.
  double edge_amplitude = std::numeric_limits<double>::quiet_NaN();
  double edge_power = std::numeric_limits<double>::quiet_NaN();
  // How much worse the AIC is at the first sample of the search than at the change point (the
  // AIC here is -2 log-likelihood, so 1 is the change point's one-sigma interval and 4 its two
  // sigmas); infinity where no change point was searched.
  double start_aic_excess = std::numeric_limits<double>::infinity();
};

// The fraction of an impact's peak at which its timing reference is taken (ReferenceCrossing).
inline constexpr double kReferenceFraction = 0.12;
// How far ahead the peak that sets an impact's reference level is sought. Long enough to span a
// linear-phase chain's pre-ringing (a resampler's or sigma-delta decimator's filter reaches
// 20-30 output samples each side of its centre at any rate), so that the ringing before a lobe
// is measured against that lobe and stays below the level. Short enough that a soft impact
// (a rubber ball's 0.8 ms contact is 40 samples at 48 kHz) whose plate response keeps growing
// for milliseconds after a weak first lobe (its contact click) is timed on that first lobe: a
// fraction of the window's largest sample falls on the first lobe or the next one depending on
// the ratio of the two, which changes from impact to impact, and the intervals then jump by a
// lobe's width (the detector suite's rubber ball: +150..+190 us on 4 of 10 impacts).
inline constexpr std::size_t kReferenceHorizonSamples = 24;
// A change point this many samples or fewer before an innovation's largest sample (see
// PickOnsetInInnovation) has a second segment too short to estimate a variance from.
inline constexpr double kDegenerateChangePointSamples = 2.0;

// Start of contact inside a window of band-passed samples that holds noise (or the tail of an
// earlier impact) followed by the rising edge of one impact, up to its first peak.
//
// Two stages (docs/history/onset_timing.md compares them and the alternatives on synthetic
// recordings):
//  1. The change point is the minimum of the Akaike information criterion of a two-segment
//     model (Maeda 1985; Sleeman & van Eck, PEPI 113, 1999), searched in [search_begin,
//     search_end). It finds the first sample that belongs to the impact, but on its own it is
//     late by most of a sample: the sound of a contact grows from zero smoothly, so its first
//     samples hide in the noise.
//  2. FitLeadingEdge (below) fits a power law to the leading edge of the impact's first lobe
//     and takes its origin. When no edge stands out of the noise the change point is kept.
//
// It also sets the impact's timing reference (reference_index, see ReferenceCrossing): from it,
// intervals between impacts do not depend on their loudness.
OnsetPick PickOnset(std::span<const float> window, std::size_t search_begin,
                    std::size_t search_end);

// PickOnset on a prediction innovation (an impact inside ringing, OnsetLocator), searched from
// search_begin up to its largest sample `largest`, with the window ending just after it as for an
// edge. But an innovation is no edge that grows to its peak: it is a burst as long as the contact
// pushes, and for a soft contact (a rubber ball's 1.3 ms) its largest sample can lie late in it.
// The AIC's second segment then holds the one or two samples up to that sample, their variance
// outweighs the burst's, and the change point lands on them: the detector suite's rubber_ball,
// 11th impact, 1.31 ms late. Where the change point lies within kDegenerateChangePointSamples of
// `largest`, burst_samples more of `innovation` after the cut are taken in and the change point
// searched again over the same span; the new pick is kept where it still stands out of the
// search's start by min_start_aic_excess (else the burst did not show where it began).
OnsetPick PickOnsetInInnovation(std::span<const float> innovation, std::size_t search_begin,
                                std::size_t largest, std::size_t burst_samples,
                                double min_start_aic_excess);

// Constant-fraction timing, the discriminator that pulse-timing electronics use against the
// amplitude walk of a fixed threshold: the time the impact's edge first reaches
// kReferenceFraction of the largest sample within a short horizon after it (its own first lobe,
// when that fraction of the window's largest sample in [from, peak_end) is reached within the
// same horizon; else, or where the lobe's level lies within the noise, the window's largest
// sample sets the level), interpolated linearly between the two samples around the crossing. The
// start of contact cannot be timed that way on a real recording chain: its anti-aliasing filter or
// resampler is linear-phase, so a click's energy already rises a few samples before contact (the
// filter's pre-ringing, up to ~5 % of the peak at 16-48 kHz), above the noise for loud impacts
// only, and any picker that looks for the first sample out of the noise fires earlier the louder
// the impact. 12 % lies above that pre-ringing and below the first lobe of a struck plate. The
// uncertainty is the noise over the edge's slope there, combined with kReferenceShapeSamples for
// the shape differences between impacts. Nothing when the level is within kLobeNoiseSigmas of the
// noise (a buried impact: the caller extrapolates the fitted edge to the level instead).
std::optional<OnsetPick> ReferenceCrossing(std::span<const float> x, std::size_t from,
                                           std::size_t peak_end, double noise_rms);

// Leading-edge fit. The contact force of a ball on a plate grows from zero (linearly for a
// half-sine or linear-spring pulse, as t^(3/2) for a Hertz contact; Johnson 1985, ch. 11) and
// every plate mode, whose impulse response starts as sin(w t) ~ t, integrates it once more,
// so the radiated sound starts as a (t - t0)^p with p ~ 3 (3.5 for Hertz); a microphone or
// filter that differentiates lowers p, an impulsive click has p = 1. The model
//     y_i = a (i - t0)^p for i > t0, 0 before,  a >= 0, p in [1, 4],
// is fitted by least squares to the samples from four before the first lobe up to the last one
// below 60 % of the lobe's extremum (above it the lobe bends over to its peak and the
// power law no longer holds). At 48 kHz the edge of a 70 us contact holds only two or three
// samples above the noise, too few to pin p down, so p has a Gaussian prior 3 +- 1 (the
// physics above) that the data overrule when they can (an impulsive onset in clean audio).
// Each sample's variance is the noise's plus 5 % of the sample for the model's own error. The
// uncertainty is the half-width of the profile-likelihood interval (cost within 1 of its minimum)
// in t0, combined in quadrature with the rms spread over the span the edge spends hidden in the
// noise (HiddenEdgeSamples, cut at the first visible sample), which the profile cannot see. A lobe
// that jumps from clean noise to half its extremum in one sample has no edge to fit: the onset is
// then put in the middle of the sample interval before it (+- 1/sqrt(12)). Returns nothing when no
// lobe stands 4 noise_rms above the noise near change_point.
std::optional<OnsetPick> FitLeadingEdge(std::span<const float> x, std::size_t change_point,
                                        double noise_rms);

// Samples after t0 during which an edge y = amplitude (i - t0)^power stays below the picker's
// lobe threshold of 4 noise_rms, i.e. hidden in the noise; 0 without noise. The picker adds the
// rms spread over this span (cut at the first visible sample) to the stated uncertainty.
double HiddenEdgeSamples(double amplitude, double power, double noise_rms);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_PICKER_H_
