#include "detector/band_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

std::vector<float> FilterAll(BandFilter& filter, const std::vector<float>& input, size_t block) {
  std::vector<float> output;
  for (size_t at = 0; at < input.size(); at += block) {
    filter.Process(std::span<const float>(input).subspan(at, std::min(block, input.size() - at)),
                   output);
  }
  filter.Finish(output);
  return output;
}

double SteadyGainDb(int rate, double low_hz, double high_hz, double tone_hz) {
  BandFilter filter(rate, low_hz, high_hz);
  std::vector<float> tone(static_cast<size_t>(rate));  // 1 s
  for (size_t i = 0; i < tone.size(); ++i) {
    tone[i] = static_cast<float>(std::sin(2 * std::numbers::pi * tone_hz * i / rate));
  }
  const auto out = FilterAll(filter, tone, 4000);
  double in_power = 0, out_power = 0;
  for (size_t i = tone.size() / 2; i < tone.size(); ++i) {  // after the transient
    in_power += double{tone[i]} * tone[i];
    out_power += double{out[i]} * out[i];
  }
  return 10 * std::log10(out_power / in_power);
}

TEST(BandFilter, PassesTheImpactBandAndRemovesHumAndDc) {
  // A 4th-order Butterworth high-pass at 300 Hz attenuates by 80 log10(300/f) dB below the
  // edge: 62 dB at 50 Hz; 40 dB is asked to leave margin for the kernel's truncation.
  EXPECT_LT(SteadyGainDb(48000, 300, 0, 50), -40);
  EXPECT_LT(SteadyGainDb(48000, 300, 0, 60), -40);
  // At 5 kHz the high-pass is flat to 1e-4 dB analytically; 0.05 dB allows float round-off.
  EXPECT_NEAR(SteadyGainDb(48000, 300, 0, 5000), 0.0, 0.05);
  // A low-pass edge at 8 kHz: -3 dB at the edge by definition of Butterworth (+-0.2 dB for
  // the bilinear transform's warping, which is pre-compensated at the edge).
  EXPECT_NEAR(SteadyGainDb(48000, 300, 8000, 8000), -3.01, 0.2);
  const auto kernel = DesignBandKernel(48000, 300, 0);
  // Zero DC gain: the kernel sums to zero (to float round-off over its length).
  EXPECT_NEAR(std::accumulate(kernel.begin(), kernel.end(), 0.0), 0.0, 1e-4);
}

TEST(BandFilter, BlockSizeDoesNotChangeTheOutput) {
  std::vector<float> input(50000);
  for (size_t i = 0; i < input.size(); ++i) {
    input[i] = static_cast<float>(std::sin(0.013 * i * i / 1000.0) + 0.1);
  }
  BandFilter a(44100, 300, 0), b(44100, 300, 0);
  const auto whole = FilterAll(a, input, input.size());
  const auto pieces = FilterAll(b, input, 977);
  ASSERT_EQ(whole.size(), input.size());
  ASSERT_EQ(pieces.size(), input.size());
  // Same arithmetic in a different grouping: equal to float round-off.
  for (size_t i = 0; i < input.size(); i += 97) EXPECT_NEAR(whole[i], pieces[i], 1e-5) << i;
}

TEST(BandFilter, IsCausalSoNothingPrecedesAnOnset) {
  BandFilter filter(48000, 300, 0);
  std::vector<float> impulse(20000, 0.0f);
  impulse[10000] = 1.0f;
  const auto out = FilterAll(filter, impulse, 3000);
  // Overlap-save with a causal kernel: exactly zero before the impulse up to FFT round-off
  // (1e-6 of the impulse).
  for (size_t i = 0; i < 10000; ++i) ASSERT_LT(std::fabs(out[i]), 1e-6f) << i;
  EXPECT_GT(out[10000], 0.5f);
}

TEST(BandFilter, RejectsBandEdgesOutsideTheRecordingsRange) {
  EXPECT_THROW(BandFilter(8000, 5000, 0), ConfigError);
  EXPECT_THROW(BandFilter(48000, 0, 0), ConfigError);
  EXPECT_THROW(BandFilter(48000, 1000, 500), ConfigError);
}

}  // namespace
}  // namespace bouncecal::audio
