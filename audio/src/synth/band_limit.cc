#include "synth/band_limit.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "synth/reverb.h"

namespace bouncecal::audio {

void BandLimit(double cutoff_hz, double transition_hz, double sample_rate_hz,
               std::span<float> signal) {
  if (signal.empty()) return;
  // Blackman: transition width ~5.5 rate / taps.
  const auto half = static_cast<size_t>(std::ceil(2.75 * sample_rate_hz / transition_hz));
  const size_t taps = 2 * half + 1;
  std::vector<double> kernel(taps);
  const double fc = cutoff_hz / sample_rate_hz;
  double sum = 0.0;
  for (size_t k = 0; k < taps; ++k) {
    const double n = static_cast<double>(k) - static_cast<double>(half);
    const double sinc =
        n == 0.0 ? 2.0 * fc : std::sin(2.0 * std::numbers::pi * fc * n) / (std::numbers::pi * n);
    const double x =
        2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(taps - 1);
    const double window = 0.42 - 0.5 * std::cos(x) + 0.08 * std::cos(2.0 * x);
    kernel[k] = sinc * window;
    sum += kernel[k];
  }
  for (double& value : kernel) value /= sum;  // unit DC gain
  // AddConvolution adds (x * tail) to x; with tail = h - delta the result is x * h, the causal
  // filter output, which lags by `half` samples: padding the input with `half` zeros and reading
  // the output `half` samples later makes it zero-phase.
  kernel[0] -= 1.0;
  std::vector<float> padded(signal.size() + half, 0.0f);
  std::copy(signal.begin(), signal.end(), padded.begin());
  AddConvolution(kernel, padded);
  std::copy(padded.begin() + static_cast<std::ptrdiff_t>(half), padded.end(), signal.begin());
}

}  // namespace bouncecal::audio
