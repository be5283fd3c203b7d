#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_MODAL_IMPACT_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_MODAL_IMPACT_H_

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {

// The first sample index i whose time i / sample_rate_hz is at or after t_s, robust to the
// rounding of t_s * sample_rate_hz (so a sample exactly at an onset counts as after it).
std::int64_t FirstSampleAtOrAfter(double t_s, double sample_rate_hz);

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

  std::complex<double> Integral(double x_s) const;  // I(x)
  std::complex<double> pole() const { return s_; }
  double gain() const { return gain_; }
  double contact_s() const { return contact_s_; }
  const std::complex<double>& contact_integral() const { return after_contact_; }  // I(tau)

 private:
  double gain_;
  double contact_s_;
  std::complex<double> s_;
  std::complex<double> after_contact_;  // I(tau)
  double ring_duration_s_;
};

// One excitation of a mode bank: a unit-area half-sine of contact_s starting at arrival_s,
// scaled by scale.
struct ModalExcitation {
  double arrival_s = 0.0;
  double scale = 1.0;
  double contact_s = 1e-4;
};

// Adds the response of every mode to every excitation to out (out[i] at time i / rate), with
// the same closed-form values as ModalImpact (exact at fractional onsets). After each contact
// the responses of one mode to all excitations are a sum of its own complex exponential, so
// they are carried as ONE recursively decaying complex state per mode: the cost is
// modes x samples, not modes x impacts x ring length, which matters for dense plates ringing
// for seconds under tens of impacts. A state that has decayed below 1e-12 (240 dB under full
// scale) is dropped until the next excitation.
void RenderModalExcitations(std::span<const PlateMode> modes,
                            std::span<const ModalExcitation> excitations, double sample_rate_hz,
                            std::span<float> out);

// A bank of modes excited together by one contact.
class ModalImpact {
 public:
  ModalImpact(std::span<const PlateMode> modes, double contact_duration_s);

  double Evaluate(double t_s) const;
  void Add(double onset_s, double scale, double sample_rate_hz, std::int64_t first_index,
           std::span<float> out) const;
  double ring_duration_s() const { return ring_duration_s_; }

  // Largest |y| at the sample times 0, 1/rate, ... up to span_s after the onset: the peak an
  // onset on a sample would show, used to give amplitudes a meaning in full-scale units.
  double SampledPeak(double sample_rate_hz, double span_s) const;

 private:
  std::vector<PlateMode> plate_modes_;
  double contact_s_;
  std::vector<ModeResponse> modes_;
  double ring_duration_s_ = 0.0;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_MODAL_IMPACT_H_
