#include "dsp/fft_wisdom.h"

#include <fftw3.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "detector/band_filter.h"
#include "detector/ringing_residual.h"

namespace bouncecal::audio {
namespace {

bool Shipped(int size) {
  return std::find(kShippedWisdomSizes.begin(), kShippedWisdomSizes.end(), size) !=
         kShippedWisdomSizes.end();
}

// The sizes the wisdom holds are the ones the detector plans, at every rate it is used at, with
// the default band (300 Hz high-pass, no low-pass): a size missing from the list would plan with
// FFTW_ESTIMATE's slower heuristic without anyone noticing.
TEST(FftWisdom, ListsTheDetectorsTransformSizesAtEveryCommonRate) {
  for (int rate : {8000, 11025, 16000, 22050, 32000, 44100, 48000, 88200, 96000, 192000}) {
    SCOPED_TRACE(rate);
    const BandFilter filter(rate, 300.0, 0.0, {2000.0, 6000.0});
    const auto block = filter.max_latency_samples() + filter.kernel().size() - 1;
    EXPECT_TRUE(Shipped(static_cast<int>(block))) << "band filter FFT of " << block;
    const RingingResidual residual(rate, 300.0, 0.0);
    EXPECT_TRUE(Shipped(residual.window_samples()))
        << "ringing residual window of " << residual.window_samples();
  }
}

// Where FFTW accepts the shipped wisdom, it holds a plan for every listed size, forward and
// inverse, on buffers allocated as RealFft allocates them (FFTW_WISDOM_ONLY returns no plan for
// a problem the wisdom does not hold): the wisdom file was generated from the list as it is.
// Another FFTW build, or a CPU without AVX, refuses the wisdom as a whole; there the plans are
// FFTW_ESTIMATE's and this test has nothing to check.
TEST(FftWisdom, HoldsAPlanForEveryListedSize) {
  if (!ImportShippedFftwfWisdom()) {
    GTEST_SKIP() << fftwf_version << " refuses the shipped wisdom (another build or no AVX)";
  }
  for (int size : kShippedWisdomSizes) {
    SCOPED_TRACE(size);
    float* real = fftwf_alloc_real(static_cast<size_t>(size));
    fftwf_complex* spectrum = fftwf_alloc_complex(static_cast<size_t>(size / 2 + 1));
    ASSERT_NE(real, nullptr);
    ASSERT_NE(spectrum, nullptr);
    fftwf_plan forward = fftwf_plan_dft_r2c_1d(size, real, spectrum, FFTW_WISDOM_ONLY);
    fftwf_plan inverse = fftwf_plan_dft_c2r_1d(size, spectrum, real, FFTW_WISDOM_ONLY);
    EXPECT_NE(forward, nullptr);
    EXPECT_NE(inverse, nullptr);
    if (forward != nullptr) fftwf_destroy_plan(forward);
    if (inverse != nullptr) fftwf_destroy_plan(inverse);
    fftwf_free(real);
    fftwf_free(spectrum);
  }
}

}  // namespace
}  // namespace bouncecal::audio
