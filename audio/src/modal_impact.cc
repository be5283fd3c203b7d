#include "modal_impact.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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

void ModalImpact::Add(double onset_s, double scale, double sample_rate_hz, std::int64_t first_index,
                      std::span<float> out) const {
  for (const ModeResponse& mode : modes_) {
    mode.Add(onset_s, scale, sample_rate_hz, first_index, out);
  }
}

}  // namespace bouncecal::audio
