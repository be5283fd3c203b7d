#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_FILTER_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_FILTER_H_

#include <complex>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace bouncecal::audio {

template <typename Real>
class BasicRealFft;
using RealFft = BasicRealFft<float>;  // real_fft.h

// Causal band-pass pre-filter applied by FFT overlap-save, one block at a time.
//
// The kernel is the impulse response of a 4th-order Butterworth high-pass at low_hz (removes DC,
// mains hum and its first harmonics, handling thumps) followed, when high_hz is below 0.45 of
// the sample rate, by a 4th-order Butterworth low-pass. The kernel is causal on purpose: a
// zero-phase (linear-phase) band-pass spreads pre-ringing before every impact, which moves the
// onset a picker sees earlier than the start of contact. With a causal kernel the samples
// before an onset stay noise only. Sample i of the output belongs to input sample i; the
// high-pass adds a group delay of only a few microseconds above a few kHz, and a constant delay
// cancels in every interval anyway.
class BandFilter {
 public:
  // Throws ConfigError when 0 < low_hz < high_hz < sample_rate_hz / 2 is violated (high_hz <= 0
  // means "no low-pass"). extra_high_pass_hz adds outputs (channels 1, 2, ...) that are also
  // high-passed at those frequencies, and extra_low_pass_hz > 0 one more, last, low-passed there
  // instead of at high_hz; they share the forward FFT, so each costs one inverse.
  BandFilter(int sample_rate_hz, double low_hz, double high_hz,
             const std::vector<double>& extra_high_pass_hz = {}, double extra_low_pass_hz = 0);
  BandFilter(const BandFilter&) = delete;
  BandFilter& operator=(const BandFilter&) = delete;
  ~BandFilter();

  // Filters input and appends the output that is complete so far to output; the output lags the
  // input by at most one FFT block. Finish() appends the rest, so in total output has exactly as
  // many samples as the input.
  void Process(std::span<const float> input, std::vector<float>& output);
  void Finish(std::vector<float>& output);
  // The same for all outputs: outputs[0] is the band, outputs[1 + i] the extra high-passes.
  void Process(std::span<const float> input, std::vector<std::vector<float>>& outputs);
  void Finish(std::vector<std::vector<float>>& outputs);
  // Receives, for every block completed, each output's new samples in output order: a view of
  // the filter's own buffer, valid only during the call, so a consumer can take them straight
  // into its own storage without an intermediate copy.
  using Sink = std::function<void(std::size_t output, std::span<const float> samples)>;
  void Process(std::span<const float> input, const Sink& sink);
  void Finish(const Sink& sink);

  const std::vector<float>& kernel() const { return kernel_; }
  std::size_t output_count() const { return kernel_spectra_.size(); }
  // The most input samples that can be waiting for output.
  std::size_t max_latency_samples() const { return block_; }

 private:
  void FilterBlock(const Sink& sink, size_t valid);

  std::vector<float> kernel_;
  std::unique_ptr<RealFft> fft_;
  std::vector<std::vector<std::complex<float>>> kernel_spectra_;
  std::vector<std::vector<float>> single_;  // scratch for the one-output overloads
  // The input is kept in fft_->real(): history_ samples of history + pending_ new samples.
  size_t history_ = 0;     // the longest kernel's size - 1
  size_t block_ = 0;       // new samples per FFT
  long long pending_ = 0;  // new samples waiting in input_
};

// The kernel alone (for tests and documentation). extra_high_pass_hz > 0 cascades one more
// 4th-order Butterworth high-pass.
std::vector<float> DesignBandKernel(int sample_rate_hz, double low_hz, double high_hz,
                                    double extra_high_pass_hz = 0);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_FILTER_H_
