#include "dsp/real_fft.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

template <typename Real>
class RealFftTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RealFftTest, Precisions);

// Rounding of one transform of this size: a few units of the precision times log2(size).
template <typename Real>
double Tolerance(int size) {
  return 16 * std::log2(size) * std::numeric_limits<Real>::epsilon();
}

// A deterministic test signal: two tones off the bin grid and a step.
double Signal(int n) { return std::sin(0.31 * n) + 0.5 * std::cos(1.7 * n + 0.2) + (n > 20); }

// The forward transform is the DFT sum X_k = sum_n x_n e^{-2 pi i k n / N}, computed directly in
// double; the inverse returns size() times the signal (FFTW's unnormalised convention), for both
// precisions of the one wrapper.
TYPED_TEST(RealFftTest, ForwardIsTheDftAndInverseReturnsSizeTimesTheSignal) {
  using Real = TypeParam;
  constexpr int kSize = 64;
  BasicRealFft<Real> fft(kSize);
  auto real = fft.real();
  double scale = 0;
  for (int n = 0; n < kSize; ++n) {
    real[static_cast<size_t>(n)] = static_cast<Real>(Signal(n));
    scale = std::max(scale, std::abs(Signal(n)));
  }
  fft.Forward();
  const auto spectrum = fft.spectrum();
  ASSERT_EQ(spectrum.size(), static_cast<size_t>(kSize / 2 + 1));
  for (int k = 0; k <= kSize / 2; ++k) {
    std::complex<double> direct = 0;
    for (int n = 0; n < kSize; ++n) {
      direct += static_cast<double>(real[static_cast<size_t>(n)]) *
                std::polar(1.0, -2 * std::numbers::pi * k * n / kSize);
    }
    const std::complex<double> fast(spectrum[static_cast<size_t>(k)].real(),
                                    spectrum[static_cast<size_t>(k)].imag());
    // Each bin sums kSize terms of at most `scale`.
    EXPECT_NEAR(std::abs(fast - direct), 0, kSize * scale * Tolerance<Real>(kSize)) << "bin " << k;
  }
  const std::vector<Real> input(real.begin(), real.end());
  fft.InverseToOutput();  // keeps real(): it still holds the input
  for (int n = 0; n < kSize; ++n) {
    EXPECT_EQ(real[static_cast<size_t>(n)], input[static_cast<size_t>(n)]);
    EXPECT_NEAR(fft.output()[static_cast<size_t>(n)] / kSize, input[static_cast<size_t>(n)],
                scale * Tolerance<Real>(kSize))
        << "sample " << n;
  }
}

// The inverse from product() is the same plan on another buffer: the same output bit for bit as
// the inverse from spectrum() on the same values (no tolerance), and spectrum() is left intact.
// At the band filter's size (5120), where FFTW's plan is not a single codelet.
TYPED_TEST(RealFftTest, InverseFromTheProductBufferEqualsTheInverseFromTheSpectrum) {
  using Real = TypeParam;
  constexpr int kSize = 5120;
  BasicRealFft<Real> fft(kSize);
  auto real = fft.real();
  for (int n = 0; n < kSize; ++n) real[static_cast<size_t>(n)] = static_cast<Real>(Signal(n));
  fft.Forward();
  const auto spectrum = fft.spectrum();
  const std::vector<std::complex<Real>> forward(spectrum.begin(), spectrum.end());
  // Scaled so the product differs from the spectrum: both inverses see these values.
  for (size_t k = 0; k < spectrum.size(); ++k) {
    fft.product()[k] = forward[k] * static_cast<Real>(0.5 + 0.25 * std::sin(0.01 * k));
  }
  const std::vector<std::complex<Real>> product(fft.product().begin(), fft.product().end());
  fft.InverseProductToOutput();
  const std::vector<Real> from_product(fft.output().begin(), fft.output().end());
  for (size_t k = 0; k < spectrum.size(); ++k) {
    ASSERT_EQ(spectrum[k], forward[k]) << "bin " << k;
    spectrum[k] = product[k];
  }
  fft.InverseToOutput();
  for (size_t n = 0; n < from_product.size(); ++n) {
    ASSERT_EQ(from_product[n], fft.output()[n]) << "sample " << n;
  }
}

TYPED_TEST(RealFftTest, OddOrTooSmallSizeIsAConfigError) {
  EXPECT_THROW(BasicRealFft<TypeParam>(63), ConfigError);
  EXPECT_THROW(BasicRealFft<TypeParam>(0), ConfigError);
}

}  // namespace
}  // namespace bouncecal::audio
