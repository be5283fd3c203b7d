#include "dsp/real_fft.h"

#include <mutex>
#include <new>
#include <string>

#include "bouncecal/error.h"
#include "dsp/fft_wisdom.h"

namespace bouncecal::audio {
namespace {

// The one lock around FFTW's planners; function-local so it is constructed on first use and
// owned by this translation unit only. The two precisions' planners are separate, so one lock
// for both only serialises what could overlap, and plans are made rarely.
std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

// FFTW's functions of one precision, by the name without its prefix.
template <typename Real>
struct Fftw;

template <>
struct Fftw<float> {
  // The detector's transforms plan from measured plans shipped with the source (fft_wisdom.h).
  static void PrepareWisdom() { ImportShippedFftwfWisdom(); }
  static float* AllocReal(size_t n) { return fftwf_alloc_real(n); }
  static fftwf_complex* AllocComplex(size_t n) { return fftwf_alloc_complex(n); }
  static void Free(void* p) { fftwf_free(p); }
  static int AlignmentOf(float* p) { return fftwf_alignment_of(p); }
  static fftwf_plan PlanR2c(int n, float* in, fftwf_complex* out) {
    return fftwf_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
  }
  static fftwf_plan PlanC2r(int n, fftwf_complex* in, float* out) {
    return fftwf_plan_dft_c2r_1d(n, in, out, FFTW_ESTIMATE);
  }
  static void Destroy(fftwf_plan plan) { fftwf_destroy_plan(plan); }
  static void Execute(fftwf_plan plan) { fftwf_execute(plan); }
  static void ExecuteC2r(fftwf_plan plan, fftwf_complex* in, float* out) {
    fftwf_execute_dft_c2r(plan, in, out);
  }
};

template <>
struct Fftw<double> {
  // The synthesiser's transforms: few, and not worth shipped plans.
  static void PrepareWisdom() {}
  static double* AllocReal(size_t n) { return fftw_alloc_real(n); }
  static fftw_complex* AllocComplex(size_t n) { return fftw_alloc_complex(n); }
  static void Free(void* p) { fftw_free(p); }
  static int AlignmentOf(double* p) { return fftw_alignment_of(p); }
  static fftw_plan PlanR2c(int n, double* in, fftw_complex* out) {
    return fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
  }
  static fftw_plan PlanC2r(int n, fftw_complex* in, double* out) {
    return fftw_plan_dft_c2r_1d(n, in, out, FFTW_ESTIMATE);
  }
  static void Destroy(fftw_plan plan) { fftw_destroy_plan(plan); }
  static void Execute(fftw_plan plan) { fftw_execute(plan); }
  static void ExecuteC2r(fftw_plan plan, fftw_complex* in, double* out) {
    fftw_execute_dft_c2r(plan, in, out);
  }
};

}  // namespace

template <typename Real>
BasicRealFft<Real>::BasicRealFft(int size) : size_(size) {
  using F = Fftw<Real>;
  if (size < 2 || size % 2 != 0) {
    throw ConfigError("FFT size must be even and at least 2, got " + std::to_string(size));
  }
  std::lock_guard<std::mutex> lock(PlannerMutex());
  F::PrepareWisdom();
  real_ = F::AllocReal(static_cast<size_t>(size));
  output_ = F::AllocReal(static_cast<size_t>(size));
  spectrum_ = F::AllocComplex(static_cast<size_t>(size / 2 + 1));
  product_ = F::AllocComplex(static_cast<size_t>(size / 2 + 1));
  if (real_ != nullptr && output_ != nullptr && spectrum_ != nullptr && product_ != nullptr) {
    forward_ = F::PlanR2c(size, real_, spectrum_);
    inverse_ = F::PlanC2r(size, spectrum_, real_);
  }
  if (real_ == nullptr || output_ == nullptr || spectrum_ == nullptr || product_ == nullptr ||
      forward_ == nullptr || inverse_ == nullptr ||
      F::AlignmentOf(real_) != F::AlignmentOf(output_) ||
      F::AlignmentOf(reinterpret_cast<Real*>(spectrum_)) !=
          F::AlignmentOf(reinterpret_cast<Real*>(product_))) {
    if (forward_ != nullptr) F::Destroy(forward_);
    if (inverse_ != nullptr) F::Destroy(inverse_);
    F::Free(real_);
    F::Free(output_);
    F::Free(spectrum_);
    F::Free(product_);
    throw std::bad_alloc();
  }
}

template <typename Real>
BasicRealFft<Real>::~BasicRealFft() {
  using F = Fftw<Real>;
  std::lock_guard<std::mutex> lock(PlannerMutex());
  F::Destroy(forward_);
  F::Destroy(inverse_);
  F::Free(real_);
  F::Free(output_);
  F::Free(spectrum_);
  F::Free(product_);
}

template <typename Real>
void BasicRealFft<Real>::Forward() {
  Fftw<Real>::Execute(forward_);
}

template <typename Real>
void BasicRealFft<Real>::Inverse() {
  Fftw<Real>::Execute(inverse_);
}

// FFTW's new-array execute: the same plan on another array of the same alignment (checked in
// the constructor), so the result is the same as Inverse()'s.
template <typename Real>
void BasicRealFft<Real>::InverseToOutput() {
  Fftw<Real>::ExecuteC2r(inverse_, spectrum_, output_);
}

// The same plan on the product buffer (aligned like spectrum_, checked in the constructor):
// the same result as InverseToOutput() on the same values.
template <typename Real>
void BasicRealFft<Real>::InverseProductToOutput() {
  Fftw<Real>::ExecuteC2r(inverse_, product_, output_);
}

template class BasicRealFft<float>;
template class BasicRealFft<double>;

}  // namespace bouncecal::audio
