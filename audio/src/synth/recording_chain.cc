#include "synth/recording_chain.h"

#include <algorithm>
#include <vector>

namespace bouncecal::audio {

HighRateRange DecimatorInput(const AntiAliasingFilter& filter, std::int64_t first_output,
                             std::int64_t output_count) {
  const auto taps = static_cast<std::int64_t>(filter.taps.size());
  const std::int64_t first = first_output * filter.oversampling + filter.lead - (taps - 1);
  const std::int64_t last = (first_output + output_count - 1) * filter.oversampling + filter.lead;
  return {first, last - first + 1};
}

void Decimate(const AntiAliasingFilter& filter, std::span<const float> input,
              std::int64_t input_first, std::int64_t first_output, std::span<float> out) {
  const auto taps = static_cast<std::int64_t>(filter.taps.size());
  // Reversed, so that each output is a dot product of two ascending runs.
  const std::vector<double> reversed(filter.taps.rbegin(), filter.taps.rend());
  const std::int64_t input_end = input_first + static_cast<std::int64_t>(input.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const std::int64_t n = first_output + static_cast<std::int64_t>(i);
    const std::int64_t base = n * filter.oversampling + filter.lead - (taps - 1);
    const std::int64_t from = std::max(base, input_first);
    const std::int64_t to = std::min(base + taps, input_end);
    const double* h = reversed.data() + (from - base);
    const float* x = input.data() + (from - input_first);
    const std::int64_t length = to - from;
    // Four partial sums: independent chains the pipeline can overlap.
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::int64_t j = 0;
    for (; j + 4 <= length; j += 4) {
      s0 += h[j] * x[j];
      s1 += h[j + 1] * x[j + 1];
      s2 += h[j + 2] * x[j + 2];
      s3 += h[j + 3] * x[j + 3];
    }
    for (; j < length; ++j) s0 += h[j] * x[j];
    out[i] = static_cast<float>((s0 + s1) + (s2 + s3));
  }
}

}  // namespace bouncecal::audio
