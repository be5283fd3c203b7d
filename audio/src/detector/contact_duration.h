#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_CONTACT_DURATION_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_CONTACT_DURATION_H_

#include <span>
#include <vector>

namespace bouncecal::audio {

// Contact durations of a recording's impacts relative to its template impact, from the spectra
// of their aligned responses.
//
// Why: aligning an impact's response to the template's (response_timing.h) locks on the centroid
// of the contact force, t0 + tau/2, not on the start of contact t0; and a Hertz contact lasts
// longer the slower the impact (tau ~ v^-1/5), so the aligned onsets drift through a drop
// (+23 us over 13 bounces of a steel ball on an anvil with a 66 us contact), which biases late
// eta_k in one direction and reads as a speed trend. The same pulses that shift the centroid
// shape the spectrum: a response is the force pulse F_k filtered by the same plate and room as
// the template's, so their cross-spectrum, once aligned at the centroids, is real and equals
// |F_k / F_t| |R_t|^2. For a half-sine pulse (the Hertz and linear-spring contact,
// Johnson 1985 ch. 11) of impulse J and duration tau, |F(f)| = J h(f tau) with
// h(x) = cos(pi x) / (1 - 4 x^2): the ratio carries J_k / J_t at low frequency and the
// durations in its fall with frequency (ln h ~ -0.935 x^2). The impulse ratio gives the speed
// ratio (J = m (1 + e) v), Hertz's law the duration ratio s_k = tau_k / tau_t = (J_k / J_t)^-1/5,
// and the curvature of every impact's ratio then fixes the one unknown left, the template's
// duration tau_t, by maximum likelihood over the impacts (Gaussian residual of unknown level per
// impact: sum of ln(1 - rho_k^2)). A pulse that is not a half-sine (Hertz's is slightly more
// peaked) changes the centroid-to-width ratio by ~10 %, which the correction inherits.
struct AlignedResponse {
  // The impact's response (first differences), from the sample where its alignment's integer
  // lag puts the template's first, and as many samples as the template segment compared.
  std::span<const float> samples;
  // The alignment's sub-sample part: the response matches the template delayed by this many
  // samples.
  double fraction = 0;
  // Whether it may fix the template's duration (a band-detected impact), or only gets its ratio.
  bool informs_fit = true;
};

struct ContactDurations {
  // The template's contact duration (s); 0 where the recording does not determine it.
  double template_s = 0;
  // Jackknife standard deviation of ln(template_s) over the impacts that fixed it.
  double template_log_sd = 0;
  int impacts_used = 0;
  // tau_k / tau_t, one per response given (1 where not estimated).
  std::vector<double> ratios;
};

// templ: the template's response (first differences) from its onset, at least as long as every
// response. Responses shorter than min_samples get ratio 1 and do not enter the fit.
ContactDurations EstimateContactDurations(std::span<const float> templ,
                                          const std::vector<AlignedResponse>& responses,
                                          int sample_rate_hz, std::size_t min_samples);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_CONTACT_DURATION_H_
