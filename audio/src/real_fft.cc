#include "real_fft.h"

#include <mutex>
#include <new>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

// The one lock around FFTW's planner; function-local so it is constructed on first use and
// owned by this translation unit only.
std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

RealFft::RealFft(int size) : size_(size) {
  if (size < 2 || size % 2 != 0) {
    throw ConfigError("FFT size must be even and at least 2, got " + std::to_string(size));
  }
  std::lock_guard<std::mutex> lock(PlannerMutex());
  real_ = fftwf_alloc_real(static_cast<size_t>(size));
  output_ = fftwf_alloc_real(static_cast<size_t>(size));
  spectrum_ = fftwf_alloc_complex(static_cast<size_t>(size / 2 + 1));
  // FFTW_ESTIMATE keeps planning deterministic and instant; measured plans would make results
  // depend on timing noise on a shared machine.
  forward_ = fftwf_plan_dft_r2c_1d(size, real_, spectrum_, FFTW_ESTIMATE);
  inverse_ = fftwf_plan_dft_c2r_1d(size, spectrum_, real_, FFTW_ESTIMATE);
  if (real_ == nullptr || output_ == nullptr || spectrum_ == nullptr || forward_ == nullptr ||
      inverse_ == nullptr || fftwf_alignment_of(real_) != fftwf_alignment_of(output_)) {
    if (forward_ != nullptr) fftwf_destroy_plan(forward_);
    if (inverse_ != nullptr) fftwf_destroy_plan(inverse_);
    fftwf_free(real_);
    fftwf_free(output_);
    fftwf_free(spectrum_);
    throw std::bad_alloc();
  }
}

RealFft::~RealFft() {
  std::lock_guard<std::mutex> lock(PlannerMutex());
  if (forward_ != nullptr) fftwf_destroy_plan(forward_);
  if (inverse_ != nullptr) fftwf_destroy_plan(inverse_);
  fftwf_free(real_);
  fftwf_free(output_);
  fftwf_free(spectrum_);
}

void RealFft::Forward() { fftwf_execute(forward_); }

void RealFft::Inverse() { fftwf_execute(inverse_); }

// FFTW's new-array execute: the same plan on another array of the same alignment (checked in
// the constructor), so the result is the same as Inverse()'s.
void RealFft::InverseToOutput() { fftwf_execute_dft_c2r(inverse_, spectrum_, output_); }

}  // namespace bouncecal::audio
