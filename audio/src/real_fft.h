#ifndef BOUNCECAL_AUDIO_SRC_REAL_FFT_H_
#define BOUNCECAL_AUDIO_SRC_REAL_FFT_H_

#include <fftw3.h>

#include <complex>
#include <span>

namespace bouncecal::audio {

// RAII owner of a pair of single-precision FFTW plans (real -> half-complex spectrum and back)
// of one size, with their own aligned buffers. FFTW's planner is not thread-safe (FFTW manual,
// "Thread safety"): constructing and destroying plans is serialised by a mutex this class owns,
// so detectors may be built on several threads; executing a plan needs no lock.
class RealFft {
 public:
  // size must be even and >= 2; throws ConfigError otherwise.
  explicit RealFft(int size);
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  ~RealFft();

  int size() const { return size_; }
  // The real buffer the forward transform reads and the inverse writes (size() values).
  std::span<float> real() { return {real_, static_cast<size_t>(size_)}; }
  // The spectrum buffer (size() / 2 + 1 bins) the forward writes and the inverse reads.
  std::span<std::complex<float>> spectrum() {
    return {reinterpret_cast<std::complex<float>*>(spectrum_), static_cast<size_t>(size_ / 2 + 1)};
  }
  void Forward();  // real() -> spectrum(); real() is preserved
  // spectrum() -> real(), unnormalised: the result is size() times the original signal.
  // spectrum() is destroyed (FFTW's default for complex-to-real transforms).
  void Inverse();
  // The same into output() instead, so real() keeps the forward transform's input.
  void InverseToOutput();
  std::span<float> output() { return {output_, static_cast<size_t>(size_)}; }

 private:
  int size_ = 0;
  float* real_ = nullptr;
  float* output_ = nullptr;  // allocated like real_, so the inverse plan runs on it unchanged
  fftwf_complex* spectrum_ = nullptr;
  fftwf_plan forward_ = nullptr;
  fftwf_plan inverse_ = nullptr;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_REAL_FFT_H_
