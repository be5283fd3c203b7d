#include "modal_impact.h"

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

// First sample index whose time i / rate is at or after t_s.
std::int64_t FirstSampleAtOrAfter(double t_s, double sample_rate_hz) {
  auto index = static_cast<std::int64_t>(std::ceil(t_s * sample_rate_hz));
  while (static_cast<double>(index) / sample_rate_hz < t_s) ++index;
  while (index > 0 && static_cast<double>(index - 1) / sample_rate_hz >= t_s) --index;
  return index;
}

}  // namespace

ModeResponse::ModeResponse(const PlateMode& mode, double contact_duration_s)
    : gain_(mode.gain),
      decay_s_(mode.decay_s),
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

ModalImpact::ModalImpact(std::span<const PlateMode> modes, double contact_duration_s) {
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
  double peak = 0.0;
  const auto count = static_cast<std::int64_t>(std::min(span_s, ring_duration_s_) * sample_rate_hz);
  for (std::int64_t i = 0; i <= count; ++i) {
    peak = std::max(peak, std::abs(Evaluate(static_cast<double>(i) / sample_rate_hz)));
  }
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
  const auto size = static_cast<std::int64_t>(out.size());
  // Where each excitation's contact ends (first sample at or after it), in order.
  struct Injection {
    std::int64_t index;
    const ModalExcitation* excitation;
  };
  std::vector<Injection> injections;
  injections.reserve(excitations.size());
  for (const ModalExcitation& excitation : excitations) {
    injections.push_back(
        {FirstSampleAtOrAfter(excitation.arrival_s + excitation.contact_s, sample_rate_hz),
         &excitation});
  }
  std::sort(injections.begin(), injections.end(),
            [](const Injection& a, const Injection& b) { return a.index < b.index; });
  for (const PlateMode& mode : modes) {
    if (mode.gain == 0.0) continue;
    // During contact: evaluated directly (a handful of samples per excitation).
    for (const ModalExcitation& excitation : excitations) {
      const ModeResponse response(mode, excitation.contact_s);
      const std::int64_t start = FirstSampleAtOrAfter(excitation.arrival_s, sample_rate_hz);
      const std::int64_t stop = std::min(
          size, FirstSampleAtOrAfter(excitation.arrival_s + excitation.contact_s, sample_rate_hz));
      for (std::int64_t index = std::max<std::int64_t>(start, 0); index < stop; ++index) {
        const double t_s = static_cast<double>(index) / sample_rate_hz - excitation.arrival_s;
        out[static_cast<size_t>(index)] +=
            static_cast<float>(excitation.scale * response.Evaluate(t_s));
      }
    }
    // After contact: one complex state per mode, advanced by one multiplication per sample.
    const std::complex<double> pole(-1.0 / mode.decay_s,
                                    2.0 * std::numbers::pi * mode.frequency_hz);
    const std::complex<double> step = std::exp(pole / sample_rate_hz);
    std::complex<double> state = 0.0;
    size_t next = 0;
    std::int64_t index = injections.empty() ? size : injections.front().index;
    while (index < size) {
      while (next < injections.size() && injections[next].index == index) {
        const ModalExcitation& excitation = *injections[next].excitation;
        const ModeResponse response(mode, excitation.contact_s);
        const double t_s = static_cast<double>(index) / sample_rate_hz - excitation.arrival_s;
        state += excitation.scale * mode.gain * std::exp(pole * t_s) * response.contact_integral();
        ++next;
      }
      out[static_cast<size_t>(index)] += static_cast<float>(state.imag());
      state *= step;
      ++index;
      if (std::abs(state.real()) + std::abs(state.imag()) < kDroppedMagnitude) {
        // Silent until the next excitation: jump there.
        state = 0.0;
        if (next >= injections.size()) break;
        index = std::max(index, injections[next].index);
      }
    }
  }
}

}  // namespace bouncecal::audio
