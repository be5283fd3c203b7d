#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_RECORDING_CHAIN_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_RECORDING_CHAIN_H_

#include <cstdint>
#include <span>

#include "synth/anti_aliasing_filter.h"

namespace bouncecal::audio {

// The high-rate samples [first, first + count) that a run of output samples reads.
struct HighRateRange {
  std::int64_t first = 0;
  std::int64_t count = 0;
};
HighRateRange DecimatorInput(const AntiAliasingFilter& filter, std::int64_t first_output,
                             std::int64_t output_count);

// The decimator of a recording chain: out[i] is output sample n = first_output + i,
//   y[n] = sum_k taps[k] x[n M + lead - k],  M = filter.oversampling,
// where x[j] = input[j - input_first] inside input and 0 outside it. Only the kept outputs are
// computed (a polyphase decimator: each output is one pass over the taps, M times fewer than
// filtering at the high rate and then dropping samples), accumulated in double.
void Decimate(const AntiAliasingFilter& filter, std::span<const float> input,
              std::int64_t input_first, std::int64_t first_output, std::span<float> out);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_RECORDING_CHAIN_H_
