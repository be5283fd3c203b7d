#include "synth/modal_impact.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

// exp(-t/T) = 1e-6 after T ln(1e6): the mode is then 120 dB below its start, far under the 16-
// and 24-bit quantisation of any written file.
constexpr double kRingDecayLog = 13.815510557964274;  // ln(1e6)
// Re-anchoring the recursively advanced exponential this often keeps its relative error near
// 1e-13 even for modes ringing for seconds.
constexpr std::int64_t kReanchorSamples = 1024;

}  // namespace

std::int64_t FirstSampleAtOrAfter(double t_s, double sample_rate_hz) {
  auto index = static_cast<std::int64_t>(std::ceil(t_s * sample_rate_hz));
  while (static_cast<double>(index) / sample_rate_hz < t_s) ++index;
  while (index > 0 && static_cast<double>(index - 1) / sample_rate_hz >= t_s) --index;
  return index;
}

ModeResponse::ModeResponse(const PlateMode& mode, double contact_duration_s)
    : gain_(mode.gain),
      contact_s_(contact_duration_s),
      s_(-1.0 / mode.decay_s, 2.0 * std::numbers::pi * mode.frequency_hz),
      after_contact_(Integral(contact_duration_s)),
      ring_duration_s_(contact_duration_s + mode.decay_s * kRingDecayLog) {}

std::complex<double> ModeResponse::Integral(double x_s) const {
  // f(u) = A sin(W u) with A = pi / (2 tau), W = pi / tau. Writing sin as (e^{iWu} - e^{-iWu})/2i
  // leaves two exponential integrals; their denominators have real part 1/T > 0, so they never
  // vanish (no resonance singularity for a damped mode).
  const double tau = contact_s_;
  const double amplitude = std::numbers::pi / (2.0 * tau);
  const std::complex<double> i(0.0, 1.0);
  const std::complex<double> w = i * (std::numbers::pi / tau);
  const std::complex<double> a = w - s_;
  const std::complex<double> b = -w - s_;
  const std::complex<double> sum = (std::exp(a * x_s) - 1.0) / a - (std::exp(b * x_s) - 1.0) / b;
  return amplitude * sum / (2.0 * i);
}

double ModeResponse::Evaluate(double t_s) const {
  if (t_s < 0.0) return 0.0;
  const std::complex<double> integral = t_s < contact_s_ ? Integral(t_s) : after_contact_;
  return gain_ * (std::exp(s_ * t_s) * integral).imag();
}

void ModeResponse::Add(double onset_s, double scale, double sample_rate_hz,
                       std::int64_t first_index, std::span<float> out) const {
  if (gain_ == 0.0 || scale == 0.0) return;
  const auto out_end = first_index + static_cast<std::int64_t>(out.size());
  const std::int64_t start = std::max(FirstSampleAtOrAfter(onset_s, sample_rate_hz), first_index);
  const std::int64_t stop =
      std::min(out_end, FirstSampleAtOrAfter(onset_s + ring_duration_s_, sample_rate_hz));
  const double factor = scale * gain_;
  const std::complex<double> step = std::exp(s_ / sample_rate_hz);
  std::complex<double> z;
  std::int64_t anchored_at = -1;
  for (std::int64_t index = start; index < stop; ++index) {
    const double t_s = static_cast<double>(index) / sample_rate_hz - onset_s;
    double y;
    if (t_s < contact_s_) {
      y = (std::exp(s_ * t_s) * Integral(t_s)).imag();
    } else {
      if (anchored_at < 0 || index - anchored_at >= kReanchorSamples) {
        z = std::exp(s_ * t_s) * after_contact_;
        anchored_at = index;
      } else {
        z *= step;
      }
      y = z.imag();
    }
    out[static_cast<size_t>(index - first_index)] += static_cast<float>(factor * y);
  }
}

ModalImpact::ModalImpact(std::span<const PlateMode> modes, double contact_duration_s)
    : plate_modes_(modes.begin(), modes.end()), contact_s_(contact_duration_s) {
  modes_.reserve(modes.size());
  for (const PlateMode& mode : modes) {
    modes_.emplace_back(mode, contact_duration_s);
    ring_duration_s_ = std::max(ring_duration_s_, modes_.back().ring_duration_s());
  }
}

double ModalImpact::Evaluate(double t_s) const {
  double sum = 0.0;
  for (const ModeResponse& mode : modes_) sum += mode.Evaluate(t_s);
  return sum;
}

double ModalImpact::SampledPeak(double sample_rate_hz, double span_s) const {
  // Rendered through the recursive bank renderer (equal to Evaluate to rounding, tested): one
  // complex exponential per sample and mode here would dominate a whole synthesis.
  const auto count = static_cast<size_t>(std::min(span_s, ring_duration_s_) * sample_rate_hz) + 1;
  std::vector<float> rendered(count, 0.0f);
  const ModalExcitation excitation{0.0, 1.0, contact_s_};
  RenderModalExcitations(plate_modes_, std::span(&excitation, 1), sample_rate_hz, rendered);
  double peak = 0.0;
  for (float value : rendered) peak = std::max(peak, std::abs(double{value}));
  return peak;
}

void ModalImpact::Add(double onset_s, double scale, double sample_rate_hz, std::int64_t first_index,
                      std::span<float> out) const {
  for (const ModeResponse& mode : modes_) {
    mode.Add(onset_s, scale, sample_rate_hz, first_index, out);
  }
}

void RenderModalExcitations(std::span<const PlateMode> modes,
                            std::span<const ModalExcitation> excitations, double sample_rate_hz,
                            std::span<float> out) {
  constexpr double kDroppedMagnitude = 1e-12;
  constexpr std::int64_t kChunkSamples = 512;
  const auto size = static_cast<std::int64_t>(out.size());

  // During contact: evaluated directly (a handful of samples per excitation and mode).
  for (const ModalExcitation& excitation : excitations) {
    const std::int64_t start =
        std::max<std::int64_t>(0, FirstSampleAtOrAfter(excitation.arrival_s, sample_rate_hz));
    const std::int64_t stop = std::min(
        size, FirstSampleAtOrAfter(excitation.arrival_s + excitation.contact_s, sample_rate_hz));
    if (start >= stop) continue;
    for (const PlateMode& mode : modes) {
      const ModeResponse response(mode, excitation.contact_s);
      for (std::int64_t index = start; index < stop; ++index) {
        const double t_s = static_cast<double>(index) / sample_rate_hz - excitation.arrival_s;
        out[static_cast<size_t>(index)] +=
            static_cast<float>(excitation.scale * response.Evaluate(t_s));
      }
    }
  }

  // After contact: one complex state per mode, advanced by one multiplication per sample. The
  // state is carried as two doubles (std::complex's operator* guards against inf/nan with a
  // library call per sample), and four modes advance together so their independent
  // multiply chains overlap in the pipeline instead of waiting on each other's latency.
  struct ModeState {
    std::complex<double> pole;
    double step_re, step_im;
    double re = 0.0, im = 0.0;
  };
  std::vector<ModeState> states;
  for (const PlateMode& mode : modes) {
    if (mode.gain == 0.0) continue;
    const std::complex<double> pole(-1.0 / mode.decay_s,
                                    2.0 * std::numbers::pi * mode.frequency_hz);
    const std::complex<double> step = std::exp(pole / sample_rate_hz);
    states.push_back({pole, step.real(), step.imag()});
  }
  std::vector<const PlateMode*> audible;
  for (const PlateMode& mode : modes) {
    if (mode.gain != 0.0) audible.push_back(&mode);
  }
  // Where each excitation's contact ends (first sample at or after it), in order.
  std::vector<std::pair<std::int64_t, const ModalExcitation*>> injections;
  for (const ModalExcitation& excitation : excitations) {
    injections.emplace_back(
        FirstSampleAtOrAfter(excitation.arrival_s + excitation.contact_s, sample_rate_hz),
        &excitation);
  }
  std::stable_sort(injections.begin(), injections.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });

  std::vector<ModeState*> active;
  size_t next = 0;
  std::int64_t index = injections.empty() ? size : injections.front().first;
  while (index < size) {
    while (next < injections.size() && injections[next].first == index) {
      const ModalExcitation& excitation = *injections[next].second;
      const double t_s = static_cast<double>(index) / sample_rate_hz - excitation.arrival_s;
      for (size_t m = 0; m < states.size(); ++m) {
        const ModeResponse response(*audible[m], excitation.contact_s);
        const std::complex<double> added = excitation.scale * audible[m]->gain *
                                           std::exp(states[m].pole * t_s) *
                                           response.contact_integral();
        states[m].re += added.real();
        states[m].im += added.imag();
      }
      ++next;
    }
    const std::int64_t run_end =
        next < injections.size() ? std::min(size, injections[next].first) : size;
    while (index < run_end) {
      active.clear();
      for (ModeState& state : states) {
        if (std::abs(state.re) + std::abs(state.im) >= kDroppedMagnitude) {
          active.push_back(&state);
        } else {
          state.re = state.im = 0.0;  // decayed far below any quantisation: silent until the next
        }
      }
      if (active.empty()) {
        index = run_end;
        break;
      }
      const std::int64_t chunk_end = std::min(run_end, index + kChunkSamples);
      float* chunk = out.data() + index;
      const auto count = static_cast<size_t>(chunk_end - index);
      size_t m = 0;
      for (; m + 4 <= active.size(); m += 4) {
        ModeState& a = *active[m];
        ModeState& b = *active[m + 1];
        ModeState& c = *active[m + 2];
        ModeState& d = *active[m + 3];
        for (size_t i = 0; i < count; ++i) {
          chunk[i] += static_cast<float>(a.im + b.im + c.im + d.im);
          const double ar = a.re * a.step_re - a.im * a.step_im;
          a.im = a.re * a.step_im + a.im * a.step_re;
          a.re = ar;
          const double br = b.re * b.step_re - b.im * b.step_im;
          b.im = b.re * b.step_im + b.im * b.step_re;
          b.re = br;
          const double cr = c.re * c.step_re - c.im * c.step_im;
          c.im = c.re * c.step_im + c.im * c.step_re;
          c.re = cr;
          const double dr = d.re * d.step_re - d.im * d.step_im;
          d.im = d.re * d.step_im + d.im * d.step_re;
          d.re = dr;
        }
      }
      for (; m < active.size(); ++m) {
        ModeState& a = *active[m];
        for (size_t i = 0; i < count; ++i) {
          chunk[i] += static_cast<float>(a.im);
          const double ar = a.re * a.step_re - a.im * a.step_im;
          a.im = a.re * a.step_im + a.im * a.step_re;
          a.re = ar;
        }
      }
      index = chunk_end;
    }
  }
}

}  // namespace bouncecal::audio
