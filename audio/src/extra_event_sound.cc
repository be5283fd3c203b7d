#include "extra_event_sound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "modal_impact.h"

namespace bouncecal::audio {
namespace {

constexpr std::array<PlateMode, 4> kKnockModes = {
    {{180.0, 0.020, 1.0}, {410.0, 0.015, 0.7}, {870.0, 0.010, 0.5}, {1650.0, 0.006, 0.3}}};
constexpr double kKnockContactS = 1.5e-3;
constexpr std::array<PlateMode, 2> kThumpModes = {{{35.0, 0.08, 1.0}, {70.0, 0.04, 0.5}}};
constexpr double kThumpContactS = 0.02;

void AddModal(std::span<const PlateMode> modes, double contact_s, double arrival_s,
              double peak_amplitude, double sample_rate_hz, std::int64_t first_index,
              std::span<float> out) {
  std::vector<PlateMode> audible;
  for (const PlateMode& mode : modes) {
    if (mode.frequency_hz < 0.45 * sample_rate_hz) audible.push_back(mode);
  }
  const ModalImpact impact(audible, contact_s);
  const double peak = impact.SampledPeak(sample_rate_hz, impact.ring_duration_s());
  if (peak <= 0.0) return;
  impact.Add(arrival_s, peak_amplitude / peak, sample_rate_hz, first_index, out);
}

void AddStrayBurst(double arrival_s, double peak_amplitude, double sample_rate_hz,
                   RandomStream random, std::int64_t first_index, std::span<float> out) {
  constexpr double kAttackS = 0.003;
  constexpr double kDecayS = 0.010;
  constexpr double kLengthS = 0.060;
  // RBJ cookbook band-pass (constant 0 dB peak gain) centred on the geometric mean of the band.
  const double low_hz = 300.0;
  const double high_hz = std::min(2500.0, 0.45 * sample_rate_hz);
  const double centre_hz = std::sqrt(low_hz * high_hz);
  const double q = centre_hz / (high_hz - low_hz);
  const double w0 = 2.0 * std::numbers::pi * centre_hz / sample_rate_hz;
  const double alpha = std::sin(w0) / (2.0 * q);
  const double a0 = 1.0 + alpha;
  const double b0 = alpha / a0, b2 = -alpha / a0;
  const double a1 = -2.0 * std::cos(w0) / a0, a2 = (1.0 - alpha) / a0;

  auto start = static_cast<std::int64_t>(std::ceil(arrival_s * sample_rate_hz));
  if (static_cast<double>(start) / sample_rate_hz < arrival_s) ++start;
  const auto count = static_cast<std::int64_t>(kLengthS * sample_rate_hz);
  std::vector<double> burst(static_cast<size_t>(count));
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0, peak = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    const double x = random.Gaussian();
    const double y = b0 * x + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
    const double t_s = static_cast<double>(start + i) / sample_rate_hz - arrival_s;
    const double envelope = t_s < kAttackS
                                ? 0.5 * (1.0 - std::cos(std::numbers::pi * t_s / kAttackS))
                                : std::exp(-(t_s - kAttackS) / kDecayS);
    burst[static_cast<size_t>(i)] = y * envelope;
    peak = std::max(peak, std::abs(burst[static_cast<size_t>(i)]));
  }
  if (peak <= 0.0) return;
  for (std::int64_t i = 0; i < count; ++i) {
    const std::int64_t index = start + i - first_index;
    if (index < 0 || index >= static_cast<std::int64_t>(out.size())) continue;
    out[static_cast<size_t>(index)] +=
        static_cast<float>(burst[static_cast<size_t>(i)] * peak_amplitude / peak);
  }
}

}  // namespace

void AddExtraEventSound(SoundEventKind kind, double arrival_s, double peak_amplitude,
                        double sample_rate_hz, RandomStream random, std::int64_t first_index,
                        std::span<float> out) {
  switch (kind) {
    case SoundEventKind::kKnock:
      AddModal(kKnockModes, kKnockContactS, arrival_s, peak_amplitude, sample_rate_hz, first_index,
               out);
      break;
    case SoundEventKind::kThump:
      AddModal(kThumpModes, kThumpContactS, arrival_s, peak_amplitude, sample_rate_hz, first_index,
               out);
      break;
    case SoundEventKind::kStray:
      AddStrayBurst(arrival_s, peak_amplitude, sample_rate_hz, random, first_index, out);
      break;
    case SoundEventKind::kBallImpact:
    case SoundEventKind::kPrecursor:
      break;  // rendered by the impact renderer; rejected by validation as extra events
  }
}

}  // namespace bouncecal::audio
