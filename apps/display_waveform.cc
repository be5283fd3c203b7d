#include "display_waveform.h"

#include <fmt/core.h>

#include <numbers>
#include <vector>

#include "bouncecal/audio/load_recording.h"
#include "bouncecal/error.h"

namespace bouncecal::apps {

WaveformColumns DisplayWaveform(const std::filesystem::path& path, int channel, double high_pass_hz,
                                int columns) {
  audio::RecordingReader reader(path);
  if (channel < 0 || channel >= reader.info().channel_count) {
    throw InputError(
        fmt::format("'{}' has {} channel(s), no channel {}; was it replaced since it "
                    "was analysed?",
                    path.string(), reader.info().channel_count, channel));
  }
  const int rate_hz = reader.info().sample_rate_hz;
  MinMaxDecimator decimator(reader.info().header_frames, columns, rate_hz);
  // First-order RC high-pass, y[n] = a (y[n-1] + x[n] - x[n-1]) with a = RC / (RC + dt).
  const double rc_s = 1.0 / (2 * std::numbers::pi * high_pass_hz);
  const double a = rc_s / (rc_s + 1.0 / rate_hz);
  double previous_in = 0, previous_out = 0;
  std::vector<std::vector<float>> channels;
  std::vector<float> filtered;
  while (reader.ReadBlock(channels, 1 << 15)) {
    const auto& samples = channels[static_cast<std::size_t>(channel)];
    filtered.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      previous_out = a * (previous_out + samples[i] - previous_in);
      previous_in = samples[i];
      filtered[i] = static_cast<float>(previous_out);
    }
    decimator.Add(filtered);
  }
  return decimator.Finish();
}

}  // namespace bouncecal::apps
