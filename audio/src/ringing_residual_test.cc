#include "ringing_residual.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

constexpr int kRate = 48000;

// Two plate-like modes ringing from t = 0 (decays of 0.25 s and 0.12 s).
float Ringing(int i) {
  const double t = static_cast<double>(i) / kRate;
  return static_cast<float>(0.5 * std::exp(-t / 0.25) * std::sin(2 * std::numbers::pi * 1250 * t) +
                            0.3 * std::exp(-t / 0.12) * std::sin(2 * std::numbers::pi * 4130 * t));
}

// Mean residual power of the frames that complete in [from, to) samples.
std::vector<double> Residuals(const std::vector<float>& x) {
  RingingResidual residual(kRate, 300.0, 0.0);
  std::vector<double> powers;
  for (float v : x) {
    if (residual.Push(v)) powers.push_back(residual.power());
  }
  return powers;
}

TEST(RingingResidual, DecayingModesArePredictedAndLeaveAlmostNoResidual) {
  std::vector<float> x(kRate / 5);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = Ringing(static_cast<int>(i));
  const auto powers = Residuals(x);
  ASSERT_GT(powers.size(), 20u);
  // The ringing's power at the end is about 0.5^2/2 e^(-2*0.2/0.25) = 0.025. One damped
  // sinusoid is an exact geometric sequence in every bin; two modes leak into each other's
  // bins through the Hann side lobes (-31 dB), which breaks that a little: the residual stays
  // 30 dB below the signal (measured ~37 dB), where a band-energy rise could not see anything.
  const double signal_power = 0.125 * std::exp(-2 * 0.2 / 0.25);
  for (std::size_t f = 4; f < powers.size(); ++f) EXPECT_LT(powers[f], 1e-3 * signal_power) << f;
}

TEST(RingingResidual, AWeakClickInsideLoudRingingStandsOut) {
  std::vector<float> x(kRate / 5);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = Ringing(static_cast<int>(i));
  // A click at 0.1 s, 16 dB below the ringing's amplitude and ~35 dB below its energy in a
  // frame: no band-energy rise would show it.
  const std::size_t at = kRate / 10;
  x[at] += 0.05f;
  x[at + 1] -= 0.035f;
  const auto powers = Residuals(x);
  double before = 0;
  double after = 0;
  const std::size_t hop = 64;  // half of the 128-sample window at 48 kHz
  for (std::size_t f = 4; f < powers.size(); ++f) {
    const std::size_t end = f * hop + 128;
    if (end < at && end + kRate / 50 > at) before = std::max(before, powers[f]);
    if (end > at + 32 && end < at + 128) after = std::max(after, powers[f]);
  }
  // The detector's default rise threshold is 10 dB over the preceding 12 ms; the click must
  // clear it in the residual (measured ~13 dB).
  EXPECT_GT(after, 10.0 * before);
}

}  // namespace
}  // namespace bouncecal::audio
