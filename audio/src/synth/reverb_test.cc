#include "synth/reverb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

namespace bouncecal::audio {
namespace {

TEST(DiffuseReverb, TailHasTheRequestedEnergyPredelayAndRt60) {
  ReverbOptions options;
  options.rt60_s = 0.5;
  options.direct_to_reverberant_db = 8.0;
  options.predelay_s = 0.004;
  const double rate = 48000;
  const std::vector<double> tail = DiffuseTail(options, rate, RandomStream(1, 2));
  // Energy: scaled exactly (rounding only).
  const double energy = std::inner_product(tail.begin(), tail.end(), tail.begin(), 0.0);
  EXPECT_NEAR(10 * std::log10(1.0 / energy), 8.0, 1e-9);
  // Nothing before the predelay (192 samples), something right after.
  for (size_t i = 0; i < 192; ++i) ASSERT_EQ(tail[i], 0.0);
  EXPECT_NE(tail[192], 0.0);
  // Schroeder backward integration (Schroeder 1965): the energy decay curve of an exponential
  // tail falls linearly in dB; fit its slope between -5 and -35 dB (ISO 3382's T30 range).
  std::vector<double> decay(tail.size());
  double remaining = 0.0;
  for (size_t i = tail.size(); i-- > 0;) {
    remaining += tail[i] * tail[i];
    decay[i] = 10 * std::log10(remaining / energy);
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t i = 192; i < tail.size(); ++i) {
    if (decay[i] > -5 || decay[i] < -35) continue;
    const double t = static_cast<double>(i) / rate;
    sx += t;
    sy += decay[i];
    sxx += t * t;
    sxy += t * decay[i];
    ++n;
  }
  const double slope_db_per_s = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  // Gaussian fluctuation of a 0.5 s tail at 48 kHz moves the fitted T30 by well under 2 %.
  EXPECT_NEAR(-60.0 / slope_db_per_s, 0.5, 0.01);
}

TEST(DiffuseReverb, FftConvolutionEqualsDirectConvolutionAndKeepsSilenceBeforeTheInput) {
  RandomStream random(5, 6);
  std::vector<double> tail(3000, 0.0);
  for (size_t i = 100; i < tail.size(); ++i) tail[i] = 0.01 * random.Gaussian();
  std::vector<float> signal(20000, 0.0f);
  for (size_t i = 7000; i < 7400; ++i) signal[i] = static_cast<float>(random.Gaussian());
  for (size_t i = 12000; i < 12100; ++i) signal[i] = static_cast<float>(random.Gaussian());
  const std::vector<float> dry = signal;
  AddConvolution(tail, signal);
  double worst = 0.0;
  for (size_t n = 0; n < signal.size(); ++n) {
    double wet = 0.0;
    for (size_t k = 0; k < tail.size() && k <= n; ++k) wet += dry[n - k] * tail[k];
    worst = std::max(worst, std::abs(signal[n] - (dry[n] + wet)));
  }
  // Double FFT rounding is ~1e-15; the float result rounds at ~1e-7 of values up to ~4.
  EXPECT_LT(worst, 1e-6);
  // Before the input plus the tail's 100 leading zeros the output is the dry input, exactly.
  for (size_t n = 0; n < 7100; ++n) ASSERT_EQ(signal[n], dry[n]) << n;
}

}  // namespace
}  // namespace bouncecal::audio
