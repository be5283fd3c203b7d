#ifndef BOUNCECAL_AUDIO_WRITE_RECORDING_H_
#define BOUNCECAL_AUDIO_WRITE_RECORDING_H_

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "bouncecal/audio/recording.h"

namespace bouncecal::audio {

enum class AudioContainer { kWav, kFlac };
// Sample encodings; FLAC holds only kPcm16 and kPcm24.
enum class SampleEncoding { kPcm16, kPcm24, kPcm32, kFloat };

std::string_view ToString(SampleEncoding encoding);  // "pcm16", "pcm24", "pcm32", "float"
// Throws ConfigError naming the accepted values.
SampleEncoding SampleEncodingFromString(std::string_view name);
std::string_view ToString(AudioContainer container);  // "wav", "flac"
// kFlac for a ".flac" extension (any case), kWav otherwise.
AudioContainer ContainerForPath(const std::filesystem::path& path);

struct WriteRecordingOptions {
  AudioContainer container = AudioContainer::kWav;
  SampleEncoding encoding = SampleEncoding::kPcm16;
};

struct WriteRecordingSummary {
  std::int64_t frames = 0;
  int channels = 0;
  int sample_rate_hz = 0;
  // Samples beyond full scale (|x| > 1) that integer encodings clipped; float keeps them.
  std::int64_t clipped_samples = 0;
};

// Writes the channels (equal rates and lengths) as one interleaved file through libsndfile,
// atomically: a temporary in the same folder is renamed onto path only when complete, so a
// failure never leaves a half-written or damaged file. Throws ConfigError for an empty channel
// list, unequal channels or an encoding the container cannot hold, OutputError when the file
// cannot be written.
WriteRecordingSummary WriteRecording(const std::filesystem::path& path,
                                     std::span<const Recording> channels,
                                     const WriteRecordingOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_WRITE_RECORDING_H_
