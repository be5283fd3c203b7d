#ifndef BOUNCECAL_AUDIO_SRC_DSP_REAL_FFT_H_
#define BOUNCECAL_AUDIO_SRC_DSP_REAL_FFT_H_

#include <fftw3.h>

#include <complex>
#include <span>

namespace bouncecal::audio {

// FFTW's types of one precision: libfftw3f (float) and libfftw3 (double) are separate libraries
// with the same interface under other prefixes.
template <typename Real>
struct FftwTypes;
template <>
struct FftwTypes<float> {
  using Complex = fftwf_complex;
  using Plan = fftwf_plan;
};
template <>
struct FftwTypes<double> {
  using Complex = fftw_complex;
  using Plan = fftw_plan;
};

// RAII owner of a pair of FFTW plans (real -> half-complex spectrum and back) of one size and
// precision, with their own aligned buffers: the one FFT wrapper of the module. The detector's
// filters run in single precision (RealFft); the synthesiser's filter design and convolutions
// in double (RealFftDouble). Plans are FFTW_ESTIMATE: deterministic and instant, where plans
// measured at run time would make results depend on timing noise on a shared machine; in single
// precision they come from measured plans shipped with the source where FFTW accepts them
// (fft_wisdom.h: the same plans in every run, 9-47 % less time per transform than the
// heuristic's). FFTW's planner is not
// thread-safe (FFTW manual, "Thread safety"): constructing and destroying plans, of either
// precision, is serialised by one mutex, so detectors may be built on several threads;
// executing a plan needs no lock.
template <typename Real>
class BasicRealFft {
 public:
  using Complex = typename FftwTypes<Real>::Complex;
  using Plan = typename FftwTypes<Real>::Plan;

  // size must be even and >= 2; throws ConfigError otherwise, std::bad_alloc when FFTW cannot
  // allocate or plan.
  explicit BasicRealFft(int size);
  BasicRealFft(const BasicRealFft&) = delete;
  BasicRealFft& operator=(const BasicRealFft&) = delete;
  ~BasicRealFft();

  int size() const { return size_; }
  // The real buffer the forward transform reads and the inverse writes (size() values).
  std::span<Real> real() { return {real_, static_cast<size_t>(size_)}; }
  // The spectrum buffer (size() / 2 + 1 bins) the forward writes and the inverse reads.
  std::span<std::complex<Real>> spectrum() {
    return {reinterpret_cast<std::complex<Real>*>(spectrum_), static_cast<size_t>(size_ / 2 + 1)};
  }
  void Forward();  // real() -> spectrum(); real() is preserved
  // spectrum() -> real(), unnormalised: the result is size() times the original signal.
  // spectrum() is destroyed (FFTW's default for complex-to-real transforms).
  void Inverse();
  // The same into output() instead, so real() keeps the forward transform's input.
  void InverseToOutput();
  std::span<Real> output() { return {output_, static_cast<size_t>(size_)}; }
  // A second spectrum buffer, allocated like spectrum(), and the inverse from it into
  // output(): spectrum() then keeps the forward transform's result, so a filter that applies
  // several kernels to one input spectrum need not copy it first. Destroys product().
  std::span<std::complex<Real>> product() {
    return {reinterpret_cast<std::complex<Real>*>(product_), static_cast<size_t>(size_ / 2 + 1)};
  }
  void InverseProductToOutput();

 private:
  int size_ = 0;
  Real* real_ = nullptr;
  Real* output_ = nullptr;  // allocated like real_, so the inverse plan runs on it unchanged
  Complex* spectrum_ = nullptr;
  Complex* product_ = nullptr;  // allocated like spectrum_, for the same reason as output_
  Plan forward_ = nullptr;
  Plan inverse_ = nullptr;
};

using RealFft = BasicRealFft<float>;
using RealFftDouble = BasicRealFft<double>;

extern template class BasicRealFft<float>;
extern template class BasicRealFft<double>;

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DSP_REAL_FFT_H_
