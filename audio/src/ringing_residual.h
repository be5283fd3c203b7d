#ifndef BOUNCECAL_AUDIO_SRC_RINGING_RESIDUAL_H_
#define BOUNCECAL_AUDIO_SRC_RINGING_RESIDUAL_H_

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "real_fft.h"

namespace bouncecal::audio {

// New energy that the ringing of earlier impacts does not explain. A plate or room mode after
// an impact is an exponentially damped sinusoid, so in every bin of a short-time spectrum it
// dominates, consecutive frames form a geometric sequence X_t = X_{t-1} * z (z carries the
// phase advance over one hop and the decay). The residual X_t - X_{t-1} * (X_{t-1} / X_{t-2})
// is therefore near zero for ringing, however loud, and large when a new impact adds energy
// with a fresh phase: complex-domain onset detection (Bello, Duxbury, Davies & Sandler, IEEE
// Signal Process. Lett. 11(6), 2004), here with the decay included in the prediction. The
// ratio is limited to magnitude 1 because ringing only decays; a growing prediction from two
// noisy frames would otherwise create residual of its own.
class RingingResidual {
 public:
  // Window of about 2.7 ms (a power of two in samples, at least 16), hop half of it; bins
  // outside [band_low_hz, band_high_hz] (band_high_hz <= 0: up to Nyquist) are ignored.
  RingingResidual(int sample_rate_hz, double band_low_hz, double band_high_hz);

  int window_samples() const { return window_; }
  // Feeds one sample; true when a frame completed, its mean residual power is then power().
  bool Push(float sample) {
    buffer_[static_cast<std::size_t>(fill_++)] = sample;
    if (fill_ < window_) return false;
    Analyse();
    return true;
  }
  double power() const { return power_; }

 private:
  void Analyse();

  int window_ = 0;
  int hop_ = 0;
  int fill_ = 0;
  std::size_t first_bin_ = 0;
  std::size_t end_bin_ = 0;
  std::vector<float> buffer_;
  std::vector<float> taper_;
  std::vector<std::complex<float>> previous_;
  std::vector<std::complex<float>> before_previous_;
  std::int64_t frames_ = 0;
  double power_ = 0;
  RealFft fft_;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_RINGING_RESIDUAL_H_
