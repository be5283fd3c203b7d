#include "synth/limiter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

constexpr double kRateHz = 48000;

double PeakDb(const std::vector<float>& signal, std::size_t from, std::size_t to) {
  float peak = 0;
  for (std::size_t i = from; i < to; ++i) peak = std::max(peak, std::fabs(signal[i]));
  return 20 * std::log10(peak);
}

// A decaying 2 kHz ring of `peak` starting at sample `at` (one impact's sound).
void AddRing(std::vector<float>& signal, std::size_t at, double peak) {
  for (std::size_t i = at; i < signal.size(); ++i) {
    const double t = static_cast<double>(i - at) / kRateHz;
    signal[i] +=
        static_cast<float>(peak * std::exp(-t / 0.01) * std::sin(2 * std::numbers::pi * 2000 * t));
  }
}

// The ceiling holds for every sample, however far the gain drives the signal over it (the
// exponential approach is caught by the final hold).
TEST(Limiter, NoSampleLeavesAboveTheCeiling) {
  std::vector<float> signal(4800, 0.0f);
  for (std::size_t at : {100u, 1000u, 1010u, 3000u}) AddRing(signal, at, 0.9);
  LimiterOptions options;
  options.gain_db = 40;
  options.lookahead_s = 0.5e-3;
  ApplyLimiter(options, kRateHz, signal);
  EXPECT_LE(PeakDb(signal, 0, signal.size()), options.ceiling_dbfs + 1e-6);
}

// Where the gained signal stays under the ceiling the stage is the gain alone, sample for sample.
TEST(Limiter, UnderTheCeilingItIsTheGain) {
  std::vector<float> signal(4800, 0.0f);
  AddRing(signal, 200, 0.05);
  const auto input = signal;
  LimiterOptions options;
  options.gain_db = 20;  // 0.05 x 10 = 0.5, under the -1 dBFS ceiling (0.89)
  ApplyLimiter(options, kRateHz, signal);
  for (std::size_t i = 0; i < signal.size(); ++i) {
    ASSERT_NEAR(signal[i], 10.0f * input[i], 1e-6f) << i;
  }
}

// A click 12 dB under its bounce and 5 ms ahead of it (13 dB between their sampled peaks): with
// 18 dB of make-up gain the bounce is driven 12 dB over the ceiling and the click to it, both
// leave at the ceiling, and the difference by which the detector tells a click from its bounce is
// gone (within 1 dB).
TEST(Limiter, BringsALoudBounceDownToItsClicksLevel) {
  std::vector<float> signal(9600, 0.0f);
  const std::size_t click = 2000;
  const std::size_t bounce = click + static_cast<std::size_t>(5e-3 * kRateHz);
  AddRing(signal, click, 0.125);
  AddRing(signal, bounce, 0.5);
  const double before_db = PeakDb(signal, bounce, bounce + 240) - PeakDb(signal, click, bounce);
  ASSERT_GT(before_db, 12.0);
  LimiterOptions options;
  options.gain_db = 18;
  ApplyLimiter(options, kRateHz, signal);
  const double after_db = PeakDb(signal, bounce, bounce + 240) - PeakDb(signal, click, bounce);
  EXPECT_LT(std::fabs(after_db), 1.0);
}

// The gain dips up to the look-ahead before a limited peak, not before: a steady quiet tone under
// the ceiling is scaled by the gain alone until 2 ms before a spike the gain drives over it.
TEST(Limiter, TheGainDipsNoEarlierThanTheLookAhead) {
  std::vector<float> signal(4800);
  for (std::size_t i = 0; i < signal.size(); ++i) {
    signal[i] = static_cast<float>(
        0.01 * std::sin(2 * std::numbers::pi * 1000 * static_cast<double>(i) / kRateHz));
  }
  const std::size_t spike = 3000;
  signal[spike] = 0.9f;
  const auto input = signal;
  LimiterOptions options;
  options.gain_db = 20;
  options.lookahead_s = 2e-3;
  ApplyLimiter(options, kRateHz, signal);
  const auto lookahead = static_cast<std::size_t>(options.lookahead_s * kRateHz);
  for (std::size_t i = 0; i + lookahead < spike; ++i) {
    ASSERT_NEAR(signal[i], 10.0f * input[i], 1e-6f) << i;
  }
  // Within the look-ahead the gain has come down by most of the 19 dB the spike needs.
  EXPECT_LT(std::fabs(signal[spike - 1]), 0.5 * std::fabs(10.0f * input[spike - 1]));
}

// With a target the gain starts where it stood and moves toward it no faster than the slew: a
// steady tone 30 dB over the target is brought down by 6 dB/s, 0.6 dB after 0.1 s, and it never
// rises above the starting gain over a tone under the target.
TEST(Limiter, TheAgcSteersTowardItsTargetAtItsSlew) {
  std::vector<float> loud(static_cast<std::size_t>(0.5 * kRateHz));
  for (std::size_t i = 0; i < loud.size(); ++i) {
    loud[i] = static_cast<float>(
        0.01 * std::sin(2 * std::numbers::pi * 1000 * static_cast<double>(i) / kRateHz));
  }
  auto quiet = loud;
  for (float& v : quiet) v *= 0.01f;
  const auto input = loud;
  LimiterOptions options;
  options.gain_db = 10;
  options.target_dbfs = -73;  // the tone's RMS (-43 dBFS) is 30 dB over it
  options.slew_db_per_s = 6;
  options.level_time_s = 0.01;
  ApplyLimiter(options, kRateHz, loud);
  const auto at = static_cast<std::size_t>(0.1 * kRateHz);
  // A peak of the tone near 0.1 s (its period is 48 samples).
  std::size_t peak = at;
  for (std::size_t i = at; i < at + 48; ++i) {
    if (std::fabs(input[i]) > std::fabs(input[peak])) peak = i;
  }
  // 0.01 dB: the gain starts down once the level estimate (10 ms) passes the target's, within the
  // first ms, and 6 dB/s over a ms is 0.006 dB.
  EXPECT_NEAR(20 * std::log10(std::fabs(loud[peak] / input[peak])), 10 - 0.6, 0.01);
  options.target_dbfs = -20;
  const auto quiet_input = quiet;
  ApplyLimiter(options, kRateHz, quiet);
  for (std::size_t i = 0; i < quiet.size(); ++i) {
    ASSERT_NEAR(quiet[i], std::pow(10.0f, 0.5f) * quiet_input[i], 1e-7f) << i;
  }
}

}  // namespace
}  // namespace bouncecal::audio
