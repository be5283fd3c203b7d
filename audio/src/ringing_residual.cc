#include "ringing_residual.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace bouncecal::audio {
namespace {

constexpr double kWindowS = 5.3e-3;
constexpr int kMinWindow = 32;
constexpr int kHopsPerWindow = 4;
// How far back each bin's reference reaches: longer than the beat period of two modes a
// bin apart (~5 ms) and than a hit's own echoes (8-10 ms), so neither reads as new; shorter
// than the 30 ms of the shortest flights, so the previous impact's attack is not the reference.
constexpr double kLookbackS = 0.02;
// Power ratios are turned into dB only where a bin rose; this keeps silence out of the log.
constexpr float kTinyPower = 1e-30f;
// Lower quartile of an exponential distribution (the power of a noise bin): ln(4/3) of its mean.
constexpr double kQuartileOfMean = 0.28768207245178085;

}  // namespace

RingingResidual::RingingResidual(int sample_rate_hz, double band_low_hz, double band_high_hz)
    // The power of two within a factor 2/3 .. 4/3 of kWindowS.
    : window_(std::max(kMinWindow, static_cast<int>(std::bit_floor(static_cast<unsigned>(
                                       std::lround(1.5 * kWindowS * sample_rate_hz)))))),
      hop_(window_ / kHopsPerWindow),
      buffer_(static_cast<std::size_t>(window_)),
      taper_(static_cast<std::size_t>(window_)),
      fft_(window_) {
  const double bin_hz = static_cast<double>(sample_rate_hz) / window_;
  const auto all_bins = static_cast<std::size_t>(window_ / 2 + 1);
  first_bin_ = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(band_low_hz / bin_hz)), 1,
                                       all_bins);
  std::size_t end_bin =
      band_high_hz > 0
          ? std::min(all_bins, static_cast<std::size_t>(std::floor(band_high_hz / bin_hz)) + 1)
          : all_bins - 1;  // the Nyquist bin is real-only: half the statistics of the others
  bins_ = end_bin > first_bin_ ? end_bin - first_bin_ : 0;
  // A frame whose window overlaps the current one by half or more shares the onset's samples,
  // so the reference skips those.
  skip_frames_ = static_cast<std::size_t>(kHopsPerWindow / 2);
  lookback_frames_ = std::max<std::size_t>(
      2, static_cast<std::size_t>(std::lround(kLookbackS * sample_rate_hz / hop_)));
  history_.assign((lookback_frames_ + skip_frames_ + 1) * bins_, 0.0f);
  reference_.assign(bins_, 0.0f);
  // Periodic Hann window: its low side lobes keep a loud mode out of the neighbouring bins.
  for (int i = 0; i < window_; ++i) {
    taper_[static_cast<std::size_t>(i)] =
        static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / window_));
  }
}

void RingingResidual::Analyse() {
  auto real = fft_.real();
  for (std::size_t i = 0; i < buffer_.size(); ++i) real[i] = buffer_[i] * taper_[i];
  fft_.Forward();
  const auto spectrum = fft_.spectrum();
  const std::size_t slots = lookback_frames_ + skip_frames_ + 1;
  const auto slot = static_cast<std::size_t>(frames_) % slots;
  float* current = history_.data() + slot * bins_;
  for (std::size_t k = 0; k < bins_; ++k) current[k] = std::norm(spectrum[first_bin_ + k]);
  ++frames_;
  valid_ = frames_ >= static_cast<std::int64_t>(slots) && bins_ > 0;
  novelty_db_ = 0;
  if (valid_) {
    // The reference frames are the `lookback` oldest of the ring: all but the current one and
    // the `skip` before it. Bin-inner loops, so the maxima vectorise.
    std::fill(reference_.begin(), reference_.end(), kTinyPower);
    for (std::size_t back = skip_frames_ + 1; back < slots; ++back) {
      const float* frame = history_.data() + ((slot + slots - back) % slots) * bins_;
      for (std::size_t k = 0; k < bins_; ++k) reference_[k] = std::max(reference_[k], frame[k]);
    }
    // The sum of log ratios is the log of their product; a log per bin would cost more than
    // the FFT. The product is flushed into the sum before it could overflow.
    double sum_log10 = 0;
    double product = 1;
    for (std::size_t k = 0; k < bins_; ++k) {
      const double ratio = static_cast<double>(current[k]) / reference_[k];
      product *= std::max(1.0, ratio);
      if (product > 1e200) {
        sum_log10 += std::log10(product);
        product = 1;
      }
    }
    sum_log10 += std::log10(product);
    novelty_db_ = 10.0 * sum_log10 / static_cast<double>(bins_);
  }
  // Once per window length: frames that far apart share no samples, and the floor built from
  // these estimates (minimum statistics over seconds) needs no more.
  if (bins_ > 0 && frames_ % kHopsPerWindow == 1) {
    sorted_.assign(current, current + bins_);
    const auto quartile = sorted_.begin() + static_cast<std::ptrdiff_t>(bins_ / 4);
    std::nth_element(sorted_.begin(), quartile, sorted_.end());
    // Parseval with the Hann window's mean square 3/8: a bin of white noise of variance s^2
    // has mean power 3/8 N s^2.
    noise_power_ = *quartile / kQuartileOfMean / (0.375 * window_);
  }
  std::copy(buffer_.begin() + hop_, buffer_.end(), buffer_.begin());
  fill_ = window_ - hop_;
}

}  // namespace bouncecal::audio
