#include "synth/reverb.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>

#include "dsp/real_fft.h"

namespace bouncecal::audio {
namespace {

// 60 dB of amplitude is a factor 1000: exp(-ln(1000) t / rt60).
constexpr double kLn1000 = 6.907755278982137;
constexpr double kTailLengthRt60 = 1.5;  // 90 dB down: below any 16-bit noise floor

size_t NextPowerOfTwo(size_t n) {
  size_t power = 1;
  while (power < n) power <<= 1;
  return power;
}

}  // namespace

std::vector<double> DiffuseTail(const ReverbOptions& options, double sample_rate_hz,
                                RandomStream random) {
  const auto predelay = static_cast<size_t>(std::llround(options.predelay_s * sample_rate_hz));
  const auto length =
      predelay + static_cast<size_t>(std::ceil(kTailLengthRt60 * options.rt60_s * sample_rate_hz));
  std::vector<double> tail(length, 0.0);
  double energy = 0.0;
  for (size_t n = predelay; n < length; ++n) {
    const double t_s = static_cast<double>(n - predelay) / sample_rate_hz;
    tail[n] = random.Gaussian() * std::exp(-kLn1000 * t_s / options.rt60_s);
    energy += tail[n] * tail[n];
  }
  const double target_energy = std::pow(10.0, -options.direct_to_reverberant_db / 10.0);
  const double scale = energy > 0.0 ? std::sqrt(target_energy / energy) : 0.0;
  for (double& value : tail) value *= scale;
  return tail;
}

void AddConvolution(std::span<const double> tail, std::span<float> signal) {
  const auto first_input =
      std::find_if(signal.begin(), signal.end(), [](float x) { return x != 0; });
  if (first_input == signal.end() || tail.empty()) return;
  const auto leading_zeros = static_cast<size_t>(
      std::find_if(tail.begin(), tail.end(), [](double x) { return x != 0.0; }) - tail.begin());
  if (leading_zeros == tail.size()) return;
  const size_t first_output = static_cast<size_t>(first_input - signal.begin()) + leading_zeros;

  const size_t block = std::max<size_t>(4096, NextPowerOfTwo(tail.size()));
  const size_t fft_size = NextPowerOfTwo(block + tail.size() - 1);
  const size_t bins = fft_size / 2 + 1;
  RealFftDouble fft(static_cast<int>(fft_size));
  const auto real = fft.real();
  const auto spectrum = fft.spectrum();
  std::fill(real.begin(), real.end(), 0.0);
  std::copy(tail.begin(), tail.end(), real.begin());
  fft.Forward();
  const std::vector<std::complex<double>> tail_spectrum(spectrum.begin(), spectrum.end());

  // carry[j] holds the wet output for signal[block_start + j]; a block's output is final once
  // the block has been read, so it can be added in place without touching unread input.
  std::vector<double> carry(fft_size, 0.0);
  const double normalisation = 1.0 / static_cast<double>(fft_size);
  for (size_t block_start = 0; block_start < signal.size(); block_start += block) {
    const size_t count = std::min(block, signal.size() - block_start);
    const bool silent =
        std::all_of(signal.begin() + block_start, signal.begin() + block_start + count,
                    [](float x) { return x == 0.0f; });
    if (!silent) {
      std::fill(real.begin(), real.end(), 0.0);
      std::copy(signal.begin() + block_start, signal.begin() + block_start + count, real.begin());
      fft.Forward();
      for (size_t k = 0; k < bins; ++k)
        spectrum[k] = spectrum[k] * tail_spectrum[k] * normalisation;
      fft.Inverse();
      const size_t produced = std::min(fft_size, count + tail.size() - 1);
      for (size_t j = 0; j < produced; ++j) carry[j] += real[j];
    }
    for (size_t j = 0; j < count; ++j) {
      const size_t index = block_start + j;
      if (index >= first_output) signal[index] += static_cast<float>(carry[j]);
    }
    std::copy(carry.begin() + static_cast<std::ptrdiff_t>(count), carry.end(), carry.begin());
    std::fill(carry.end() - static_cast<std::ptrdiff_t>(count), carry.end(), 0.0);
  }
}

}  // namespace bouncecal::audio
