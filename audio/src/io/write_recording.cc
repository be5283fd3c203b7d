#include "bouncecal/audio/write_recording.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/error.h"
#include "io/sound_file.h"

namespace bouncecal::audio {
namespace {

int LibsndfileFormat(const WriteRecordingOptions& options) {
  const int container = options.container == AudioContainer::kFlac ? SF_FORMAT_FLAC : SF_FORMAT_WAV;
  switch (options.encoding) {
    case SampleEncoding::kPcm16:
      return container | SF_FORMAT_PCM_16;
    case SampleEncoding::kPcm24:
      return container | SF_FORMAT_PCM_24;
    case SampleEncoding::kPcm32:
      return container | SF_FORMAT_PCM_32;
    case SampleEncoding::kFloat:
      return container | SF_FORMAT_FLOAT;
  }
  return container | SF_FORMAT_PCM_16;
}

}  // namespace

std::string_view ToString(SampleEncoding encoding) {
  switch (encoding) {
    case SampleEncoding::kPcm16:
      return "pcm16";
    case SampleEncoding::kPcm24:
      return "pcm24";
    case SampleEncoding::kPcm32:
      return "pcm32";
    case SampleEncoding::kFloat:
      return "float";
  }
  return "unknown";
}

SampleEncoding SampleEncodingFromString(std::string_view name) {
  for (SampleEncoding encoding : {SampleEncoding::kPcm16, SampleEncoding::kPcm24,
                                  SampleEncoding::kPcm32, SampleEncoding::kFloat}) {
    if (name == ToString(encoding)) return encoding;
  }
  throw ConfigError("sample encoding '" + std::string(name) +
                    "' is unknown; use pcm16, pcm24, pcm32 or float");
}

std::string_view ToString(AudioContainer container) {
  return container == AudioContainer::kFlac ? "flac" : "wav";
}

AudioContainer ContainerForPath(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".flac" ? AudioContainer::kFlac : AudioContainer::kWav;
}

WriteRecordingSummary WriteRecording(const std::filesystem::path& path,
                                     std::span<const Recording> channels,
                                     const WriteRecordingOptions& options) {
  if (channels.empty()) {
    throw ConfigError(path.string() + ": no channels to write; give at least one channel");
  }
  const Recording& first = channels.front();
  for (const Recording& channel : channels) {
    if (channel.sample_rate_hz != first.sample_rate_hz ||
        channel.samples.size() != first.samples.size()) {
      throw ConfigError(path.string() +
                        ": channels differ in sample rate or length; every channel of one file "
                        "must share both");
    }
  }
  if (first.sample_rate_hz <= 0) {
    throw ConfigError(path.string() + ": sample_rate_hz = " + std::to_string(first.sample_rate_hz) +
                      " is not positive; give the recording's rate");
  }
  if (options.container == AudioContainer::kFlac &&
      (options.encoding == SampleEncoding::kPcm32 || options.encoding == SampleEncoding::kFloat)) {
    throw ConfigError(path.string() + ": FLAC cannot hold " +
                      std::string(ToString(options.encoding)) + " samples; use pcm16 or pcm24");
  }

  WriteRecordingSummary summary;
  summary.frames = static_cast<std::int64_t>(first.samples.size());
  summary.channels = static_cast<int>(channels.size());
  summary.sample_rate_hz = first.sample_rate_hz;
  const bool integer = options.encoding != SampleEncoding::kFloat;

  AtomicPath atomic(path);
  {
    SoundFile file = SoundFile::OpenForWriting(atomic.temporary_path(), first.sample_rate_hz,
                                               summary.channels, LibsndfileFormat(options));
    // Interleave block by block so an hour-long file needs no second full-size copy.
    constexpr size_t kBlockFrames = 8192;
    std::vector<float> interleaved(kBlockFrames * channels.size());
    for (size_t start = 0; start < first.samples.size(); start += kBlockFrames) {
      const size_t count = std::min(kBlockFrames, first.samples.size() - start);
      for (size_t i = 0; i < count; ++i) {
        for (size_t c = 0; c < channels.size(); ++c) {
          const float sample = channels[c].samples[start + i];
          if (integer && std::abs(sample) > 1.0f) ++summary.clipped_samples;
          interleaved[i * channels.size() + c] = sample;
        }
      }
      file.WriteFrames(std::span<const float>(interleaved.data(), count * channels.size()));
    }
  }  // closed (header finalised) before the rename
  atomic.Commit();
  return summary;
}

}  // namespace bouncecal::audio
