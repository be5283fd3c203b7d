#ifndef BOUNCECAL_AUDIO_RECORDING_H_
#define BOUNCECAL_AUDIO_RECORDING_H_

#include <filesystem>
#include <vector>

namespace bouncecal::audio {

// One channel of a recording at its native sample rate. Timing must stay exact, so nothing is
// ever resampled: sample i sits at time i / sample_rate_hz from the first sample of the file.
struct Recording {
  std::filesystem::path source_path;  // empty for synthesised audio
  int sample_rate_hz = 0;
  int source_channel = 0;        // 0-based channel of the source these samples came from
  int source_channel_count = 1;  // channels the source file has
  std::vector<float> samples;    // full scale is +-1

  double duration_s() const {
    return sample_rate_hz > 0 ? static_cast<double>(samples.size()) / sample_rate_hz : 0.0;
  }
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_RECORDING_H_
