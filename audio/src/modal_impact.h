#ifndef BOUNCECAL_AUDIO_SRC_MODAL_IMPACT_H_
#define BOUNCECAL_AUDIO_SRC_MODAL_IMPACT_H_

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {

// The closed-form response of one decaying mode, h(t) = exp(-t / T) sin(w t), to a half-sine
// force pulse of unit area and duration tau, f(u) = (pi / 2 tau) sin(pi u / tau) on [0, tau]:
//   y(t) = Im[ exp(s t) I(min(t, tau)) ],  s = -1/T + i w,  I(x) = int_0^x f(u) exp(-s u) du,
// with I in closed form. Because y is evaluated at any real t, an onset between two samples is
// rendered exactly; for tau -> 0 it tends to the impulse response h(t).
class ModeResponse {
 public:
  ModeResponse(const PlateMode& mode, double contact_duration_s);

  // y(t) for t >= 0 (0 for t < 0).
  double Evaluate(double t_s) const;

  // Adds scale * gain * y(t_i - onset_s) to out[i], t_i = (first_index + i) / sample_rate_hz,
  // for every sample at or after the onset, until the mode has decayed by 120 dB. After the
  // contact ends the complex exponential is advanced by one multiplication per sample and
  // re-anchored every kReanchorSamples samples, so the error stays at rounding level.
  void Add(double onset_s, double scale, double sample_rate_hz, std::int64_t first_index,
           std::span<float> out) const;

  // Time after the onset until the mode has decayed by 120 dB.
  double ring_duration_s() const { return ring_duration_s_; }

 private:
  std::complex<double> Integral(double x_s) const;  // I(x)

  double gain_;
  double decay_s_;
  double contact_s_;
  std::complex<double> s_;
  std::complex<double> after_contact_;  // I(tau)
  double ring_duration_s_;
};

// A bank of modes excited together by one contact.
class ModalImpact {
 public:
  ModalImpact(std::span<const PlateMode> modes, double contact_duration_s);

  double Evaluate(double t_s) const;
  void Add(double onset_s, double scale, double sample_rate_hz, std::int64_t first_index,
           std::span<float> out) const;
  double ring_duration_s() const { return ring_duration_s_; }

 private:
  std::vector<ModeResponse> modes_;
  double ring_duration_s_ = 0.0;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_MODAL_IMPACT_H_
