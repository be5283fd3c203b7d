#include "detector/band_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "bouncecal/error.h"
#include "dsp/real_fft.h"

namespace bouncecal::audio {
namespace {

// Direct-form-I biquad; coefficients from the bilinear transform with pre-warping (R. Bristow-
// Johnson, "Audio EQ Cookbook"). Used only to generate the kernel, never on the stream.
struct Biquad {
  double b0, b1, b2, a1, a2;
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  double Step(double x) {
    const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
    return y;
  }
};

Biquad MakeBiquad(bool high_pass, double cutoff_hz, double q, int sample_rate_hz) {
  const double w0 = 2.0 * std::numbers::pi * cutoff_hz / sample_rate_hz;
  const double alpha = std::sin(w0) / (2.0 * q);
  const double c = std::cos(w0);
  const double a0 = 1.0 + alpha;
  Biquad biquad{};
  if (high_pass) {
    biquad.b0 = (1.0 + c) / 2.0 / a0;
    biquad.b1 = -(1.0 + c) / a0;
  } else {
    biquad.b0 = (1.0 - c) / 2.0 / a0;
    biquad.b1 = (1.0 - c) / a0;
  }
  biquad.b2 = biquad.b0;
  biquad.a1 = -2.0 * c / a0;
  biquad.a2 = (1.0 - alpha) / a0;
  return biquad;
}

// out = x h, bin by bin. Written out: std::complex's operator* checks for NaN/inf (C99 Annex
// G), which costs about as much as the FFT itself here; the inputs are finite by construction.
// Also compiled for AVX, picked when the library loads where the processor has it: eight
// floats per instruction instead of four, the same products (AVX has no fused multiply-add,
// which would round differently; that is FMA, not enabled here).
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void MultiplySpectra(const std::complex<float>* x, const std::complex<float>* h,
                     std::complex<float>* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const float a = x[i].real(), b = x[i].imag();
    const float c = h[i].real(), d = h[i].imag();
    out[i] = {a * c - b * d, a * d + b * c};
  }
}

// Pole quality factors of a 4th-order Butterworth filter: 1 / (2 cos(pi/8)), 1 / (2 cos(3pi/8)).
constexpr double kButterworthQ[2] = {0.54119610014619701, 1.3065629648763766};

}  // namespace

std::vector<float> DesignBandKernel(int sample_rate_hz, double low_hz, double high_hz,
                                    double extra_high_pass_hz) {
  const double nyquist_hz = sample_rate_hz / 2.0;
  if (!(low_hz > 0) || !(low_hz < nyquist_hz * 0.9)) {
    throw ConfigError("band low edge must be in (0, " + std::to_string(0.9 * nyquist_hz) +
                      ") Hz for a " + std::to_string(sample_rate_hz) + " Hz recording, got " +
                      std::to_string(low_hz) + " Hz");
  }
  const bool low_pass = high_hz > 0 && high_hz < 0.9 * nyquist_hz;
  if (high_hz > 0 && !(high_hz > low_hz)) {
    throw ConfigError("band high edge (" + std::to_string(high_hz) +
                      " Hz) must be above the low edge (" + std::to_string(low_hz) + " Hz)");
  }
  std::vector<Biquad> stages;
  for (double q : kButterworthQ) stages.push_back(MakeBiquad(true, low_hz, q, sample_rate_hz));
  if (low_pass) {
    for (double q : kButterworthQ) stages.push_back(MakeBiquad(false, high_hz, q, sample_rate_hz));
  }
  if (extra_high_pass_hz > 0) {
    for (double q : kButterworthQ) {
      stages.push_back(MakeBiquad(true, extra_high_pass_hz, q, sample_rate_hz));
    }
  }
  // The slowest pole (the high-pass's Q = 1.31 pair) decays with time constant 2Q / omega; 12
  // time constants leave the tail below 1e-5 of the peak, far under 16-bit quantisation.
  const double tau_s = 2.0 * kButterworthQ[1] / (2.0 * std::numbers::pi * low_hz);
  const size_t length = static_cast<size_t>(std::ceil(12.0 * tau_s * sample_rate_hz)) + 16;
  std::vector<float> kernel(length);
  for (size_t i = 0; i < length; ++i) {
    double x = i == 0 ? 1.0 : 0.0;
    for (auto& stage : stages) x = stage.Step(x);
    kernel[i] = static_cast<float>(x);
  }
  // Taper the last tenth so truncation adds no step to the frequency response.
  const size_t taper = length / 10;
  for (size_t i = 0; i < taper; ++i) {
    const double w = 0.5 * (1.0 + std::cos(std::numbers::pi * (i + 1) / (taper + 1)));
    kernel[length - taper + i] *= static_cast<float>(w);
  }
  return kernel;
}

BandFilter::BandFilter(int sample_rate_hz, double low_hz, double high_hz,
                       const std::vector<double>& extra_high_pass_hz, double extra_low_pass_hz)
    : kernel_(DesignBandKernel(sample_rate_hz, low_hz, high_hz)) {
  std::vector<std::vector<float>> kernels = {kernel_};
  for (double hz : extra_high_pass_hz) {
    kernels.push_back(DesignBandKernel(sample_rate_hz, low_hz, high_hz, hz));
  }
  if (extra_low_pass_hz > 0) {
    kernels.push_back(DesignBandKernel(sample_rate_hz, low_hz, extra_low_pass_hz));
  }
  std::size_t longest = 0;
  for (const auto& kernel : kernels) longest = std::max(longest, kernel.size());
  history_ = longest - 1;
  // An FFT 4-8x the kernel keeps overlap-save cost near its minimum per output sample. Sizes
  // 5 * 2^k: FFTW_ESTIMATE's plans for them ran 15-20 % faster per output sample than the
  // neighbouring powers of two (one forward and three inverse transforms, kernel of 814 taps
  // (300 Hz at 48 kHz); 5120: 5.7-6.8 ns per sample, 4096: 7.3-8.2, 8192: 9.7-11.8, 6144:
  // 8.2-10.8, minimum of 25 runs on a shared x86-64 with AVX2, FFTW 3.3.10).
  int size = 5 * 1024;
  while (static_cast<size_t>(size) < 4 * longest) size *= 2;
  fft_ = std::make_unique<RealFft>(size);
  block_ = static_cast<size_t>(size) - history_;
  const float scale = 1.0f / static_cast<float>(size);
  for (const auto& kernel : kernels) {
    auto real = fft_->real();
    std::fill(real.begin(), real.end(), 0.0f);
    for (size_t i = 0; i < kernel.size(); ++i) real[i] = kernel[i] * scale;
    fft_->Forward();
    kernel_spectra_.emplace_back(fft_->spectrum().begin(), fft_->spectrum().end());
  }
  // The input is gathered in place in the FFT's real buffer: history_ samples of history (none
  // yet: zeros), then the new ones.
  auto real = fft_->real();
  std::fill(real.begin(), real.begin() + static_cast<std::ptrdiff_t>(history_), 0.0f);
  single_.resize(kernel_spectra_.size());
}

BandFilter::~BandFilter() = default;

void BandFilter::FilterBlock(const Sink& sink, size_t valid) {
  auto real = fft_->real();
  const size_t filled = history_ + valid;
  std::fill(real.begin() + static_cast<std::ptrdiff_t>(filled), real.end(), 0.0f);
  fft_->Forward();
  const auto spectrum = fft_->spectrum();
  const auto product = fft_->product();
  const auto output = fft_->output();
  for (size_t band = 0; band < kernel_spectra_.size(); ++band) {
    // Into the product buffer, so the input spectrum serves every band without a copy.
    MultiplySpectra(spectrum.data(), kernel_spectra_[band].data(), product.data(), spectrum.size());
    // Into the separate output buffer: the real buffer keeps the input, whose newest history_
    // samples start the next block without another copy of the whole block.
    fft_->InverseProductToOutput();
    // Overlap-save: the first history_ outputs are circularly aliased; the rest are exact.
    sink(band, output.subspan(history_, valid));
  }
  // Keep the newest history_ inputs for the next block.
  std::copy(real.begin() + static_cast<std::ptrdiff_t>(valid),
            real.begin() + static_cast<std::ptrdiff_t>(filled), real.begin());
  pending_ = 0;
}

void BandFilter::Process(std::span<const float> input, const Sink& sink) {
  size_t at = 0;
  while (at < input.size()) {
    const size_t take = std::min(block_ - static_cast<size_t>(pending_), input.size() - at);
    std::copy(input.begin() + static_cast<std::ptrdiff_t>(at),
              input.begin() + static_cast<std::ptrdiff_t>(at + take),
              fft_->real().begin() + static_cast<std::ptrdiff_t>(history_) + pending_);
    pending_ += static_cast<long long>(take);
    at += take;
    if (static_cast<size_t>(pending_) == block_) FilterBlock(sink, block_);
  }
}

void BandFilter::Finish(const Sink& sink) {
  if (pending_ > 0) FilterBlock(sink, static_cast<size_t>(pending_));
}

namespace {

BandFilter::Sink AppendTo(std::vector<std::vector<float>>& outputs, std::size_t count) {
  outputs.resize(count);
  return [&outputs](std::size_t output, std::span<const float> samples) {
    outputs[output].insert(outputs[output].end(), samples.begin(), samples.end());
  };
}

}  // namespace

void BandFilter::Process(std::span<const float> input, std::vector<std::vector<float>>& outputs) {
  Process(input, AppendTo(outputs, kernel_spectra_.size()));
}

void BandFilter::Finish(std::vector<std::vector<float>>& outputs) {
  Finish(AppendTo(outputs, kernel_spectra_.size()));
}

void BandFilter::Process(std::span<const float> input, std::vector<float>& output) {
  for (auto& s : single_) s.clear();
  Process(input, single_);
  output.insert(output.end(), single_[0].begin(), single_[0].end());
}

void BandFilter::Finish(std::vector<float>& output) {
  for (auto& s : single_) s.clear();
  Finish(single_);
  output.insert(output.end(), single_[0].begin(), single_[0].end());
}

}  // namespace bouncecal::audio
