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
  for (std::size_t k = first_bin_; k < end_bin_; ++k) {
    const std::complex<float> last = previous_[k];
    const float last_norm = std::norm(before_previous_[k]);
    std::complex<float> predicted{};
    if (frames_ >= 2 && last_norm > 0) {
      // last * (last / before) = last^2 * conj(before) / |before|^2, limited to |ratio| <= 1.
      std::complex<float> ratio = last * std::conj(before_previous_[k]) / last_norm;
      const float ratio_norm = std::norm(ratio);
      if (ratio_norm > 1.0f) ratio /= std::sqrt(ratio_norm);
      predicted = last * ratio;
    }
    residual += std::norm(spectrum[k] - predicted);
    before_previous_[k] = last;
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
