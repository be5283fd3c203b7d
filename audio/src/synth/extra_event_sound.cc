#include "synth/extra_event_sound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "synth/modal_impact.h"

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

// A second-order section (RBJ audio-EQ cookbook, Butterworth Q = 1/sqrt 2), direct form I.
struct Biquad {
  double b0, b1, b2, a1, a2;
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;

  static Biquad Butterworth(double cutoff_hz, double sample_rate_hz, bool low_pass) {
    const double w0 = 2.0 * std::numbers::pi * cutoff_hz / sample_rate_hz;
    const double alpha = std::sin(w0) / std::numbers::sqrt2;
    const double cos_w0 = std::cos(w0);
    const double a0 = 1.0 + alpha;
    const double b1 = (low_pass ? 1.0 - cos_w0 : -(1.0 + cos_w0)) / a0;
    const double b0 = (low_pass ? b1 : -b1) / 2.0;
    return {b0, b1, b0, -2.0 * cos_w0 / a0, (1.0 - alpha) / a0};
  }

  double Process(double x) {
    const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
    return y;
  }
};

void AddStrayBurst(double arrival_s, double peak_amplitude, double sample_rate_hz,
                   RandomStream random, std::int64_t first_index, std::span<float> out) {
  constexpr double kAttackS = 0.003;
  constexpr double kDecayS = 0.010;
  constexpr double kLengthS = 0.060;
  // Fourth-order band-pass: two Butterworth high-pass sections at 300 Hz and two low-pass
  // sections at 2.5 kHz (24 dB/octave skirts), like the basketball file's sub-2.5 kHz event.
  const double high_hz = std::min(2500.0, 0.45 * sample_rate_hz);
  Biquad filters[] = {Biquad::Butterworth(300.0, sample_rate_hz, false),
                      Biquad::Butterworth(300.0, sample_rate_hz, false),
                      Biquad::Butterworth(high_hz, sample_rate_hz, true),
                      Biquad::Butterworth(high_hz, sample_rate_hz, true)};

  const std::int64_t start = FirstSampleAtOrAfter(arrival_s, sample_rate_hz);
  const auto count = static_cast<std::int64_t>(kLengthS * sample_rate_hz);
  std::vector<double> burst(static_cast<size_t>(count));
  double peak = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    double y = random.Gaussian();
    for (Biquad& filter : filters) y = filter.Process(y);
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
