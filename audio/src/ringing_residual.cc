#include "ringing_residual.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace bouncecal::audio {
namespace {

// Window length: short enough that an impact 12 ms after another is in a frame of its own and
// the trigger comes within a few ms of the onset, long enough (>= 16 samples) that the modes of
// a plate (kHz apart) fall in different bins.
constexpr double kWindowS = 2.7e-3;
constexpr int kMinWindow = 16;
// Added to squared magnitudes before dividing: far below any sound (a -300 dB bin), it only
// keeps digital silence from dividing 0 by 0.
constexpr float kTinyNorm = 1e-30f;

}  // namespace

RingingResidual::RingingResidual(int sample_rate_hz, double band_low_hz, double band_high_hz)
    : window_(std::max(kMinWindow, static_cast<int>(std::bit_floor(static_cast<unsigned>(
                                       std::lround(kWindowS * sample_rate_hz)))))),
      hop_(window_ / 2),
      buffer_(static_cast<std::size_t>(window_)),
      taper_(static_cast<std::size_t>(window_)),
      fft_(window_) {
  const double bin_hz = static_cast<double>(sample_rate_hz) / window_;
  const auto bins = static_cast<std::size_t>(window_ / 2 + 1);
  first_bin_ = std::min(bins, static_cast<std::size_t>(std::ceil(band_low_hz / bin_hz)));
  end_bin_ = band_high_hz > 0
                 ? std::min(bins, static_cast<std::size_t>(std::floor(band_high_hz / bin_hz)) + 1)
                 : bins;
  end_bin_ = std::max(end_bin_, first_bin_);
  // Periodic Hann window: its low side lobes keep a loud mode out of the neighbouring bins.
  for (int i = 0; i < window_; ++i) {
    taper_[static_cast<std::size_t>(i)] =
        static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / window_));
  }
  previous_.assign(bins, {});
  before_previous_.assign(bins, {});
}

void RingingResidual::Analyse() {
  auto real = fft_.real();
  for (std::size_t i = 0; i < buffer_.size(); ++i) real[i] = buffer_[i] * taper_[i];
  fft_.Forward();
  const auto spectrum = fft_.spectrum();
  double residual = 0;
  // Written out in real arithmetic and without branches: std::complex's NaN-safe multiply and
  // divide and a data-dependent branch per bin cost more than the FFT itself.
  const float use_prediction = frames_ >= 2 ? 1.0f : 0.0f;
  for (std::size_t k = first_bin_; k < end_bin_; ++k) {
    const float lr = previous_[k].real();
    const float li = previous_[k].imag();
    const float br = before_previous_[k].real();
    const float bi = before_previous_[k].imag();
    const float xr = spectrum[k].real();
    const float xi = spectrum[k].imag();
    // ratio = last / before = last * conj(before) / |before|^2, limited to |ratio| <= 1, which
    // is |last|^2 <= |before|^2: scaled by min(1, |before| / |last|).
    const float l_norm = lr * lr + li * li;
    const float b_norm = br * br + bi * bi;
    const float inverse = use_prediction / (b_norm + kTinyNorm);
    const float limit = std::min(1.0f, std::sqrt(b_norm / (l_norm + kTinyNorm)));
    const float rr = (lr * br + li * bi) * inverse * limit;
    const float ri = (li * br - lr * bi) * inverse * limit;
    const float dr = xr - (lr * rr - li * ri);
    const float di = xi - (lr * ri + li * rr);
    residual += double{dr * dr + di * di};
    before_previous_[k] = previous_[k];
    previous_[k] = spectrum[k];
  }
  ++frames_;
  // Mean square per sample (Parseval with the Hann window's mean square 3/8), so the residual
  // reads like an energy envelope in dB.
  power_ = residual / (0.375 * static_cast<double>(window_) * window_);
  std::copy(buffer_.begin() + hop_, buffer_.end(), buffer_.begin());
  fill_ = window_ - hop_;
}

}  // namespace bouncecal::audio
