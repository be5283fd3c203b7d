#include "bouncecal/audio/load_recording.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include "bouncecal/error.h"
#include "io/audio_source.h"

namespace bouncecal::audio {

std::string_view ToString(EncoderDelay delay) {
  switch (delay) {
    case EncoderDelay::kNone:
      return "none";
    case EncoderDelay::kRemoved:
      return "removed";
    case EncoderDelay::kUnknown:
      return "unknown";
  }
  return "unknown";
}

RecordingReader::RecordingReader(const std::filesystem::path& path)
    : source_(OpenAudioSource(path)), info_(source_->info()) {
  // The detector's windows are sized in seconds, so a corrupt header claiming hundreds of MHz
  // would make it allocate gigabytes (a fuzzing finding); no recorder exceeds 768 kHz.
  if (info_.sample_rate_hz > kMaxSampleRateHz) {
    throw InputError(path.string() + ": sample rate " + std::to_string(info_.sample_rate_hz) +
                     " Hz is above the " + std::to_string(kMaxSampleRateHz) +
                     " Hz maximum; the header is damaged, export the file again");
  }
  if (info_.sample_rate_hz < kMinSampleRateHz) {
    throw InputError(path.string() + ": sample rate " + std::to_string(info_.sample_rate_hz) +
                     " Hz is below the 8000 Hz minimum; impacts cannot be timed in it");
  }
}

RecordingReader::RecordingReader(RecordingReader&&) noexcept = default;
RecordingReader& RecordingReader::operator=(RecordingReader&&) noexcept = default;
RecordingReader::~RecordingReader() = default;

bool RecordingReader::ReadBlock(std::vector<std::vector<float>>& channels, std::size_t max_frames) {
  const auto channel_count = static_cast<std::size_t>(info_.channel_count);
  channels.resize(channel_count);
  interleaved_.resize(max_frames * channel_count);
  const std::int64_t got = finished_ ? 0 : source_->ReadFrames(interleaved_);
  const auto frames = static_cast<std::size_t>(got);
  // One branch-free pass over the block, and the sample-by-sample search only when it found
  // something: checking each sample with a branch cost as much as the band filter. On the bits,
  // as a signed comparison of the magnitude with the largest finite float's, so it vectorises
  // with the baseline instruction set (the float comparison did not): NaN and infinity are
  // the magnitudes above it.
  constexpr auto kMaxFiniteBits = static_cast<std::int32_t>(0x7f7fffff);
  std::int32_t non_finite = 0;
  for (std::size_t i = 0; i < frames * channel_count; ++i) {
    const auto magnitude =
        static_cast<std::int32_t>(std::bit_cast<std::uint32_t>(interleaved_[i]) & 0x7fffffffU);
    non_finite |= magnitude > kMaxFiniteBits ? 1 : 0;
  }
  if (non_finite != 0) {
    for (std::size_t i = 0; i < frames * channel_count; ++i) {
      if (!std::isfinite(interleaved_[i])) {
        throw InputError(
            info_.path.string() + ": sample " +
            std::to_string(frames_read_ + static_cast<std::int64_t>(i / channel_count)) +
            " of channel " + std::to_string(i % channel_count) +
            " is NaN or infinite; the file is damaged, re-export it");
      }
    }
  }
  if (channel_count == 1) {
    // Mono needs no de-interleaving: the block changes hands instead of being copied (the
    // strided copy took 3 % of a mono analysis); the next read reuses the old channel buffer.
    channels[0].swap(interleaved_);
    channels[0].resize(frames);
  } else {
    for (std::size_t c = 0; c < channel_count; ++c) {
      auto& channel = channels[c];
      channel.resize(frames);
      for (std::size_t f = 0; f < frames; ++f) channel[f] = interleaved_[f * channel_count + c];
    }
  }
  frames_read_ += got;
  if (got > 0) return true;
  finished_ = true;
  // A stream that ends before the announced frame count (other containers) is truncated too.
  if (info_.header_frames > 0 && info_.header_frames < (std::int64_t{1} << 62) &&
      frames_read_ < info_.header_frames) {
    throw InputError(info_.path.string() + ": truncated, only " + std::to_string(frames_read_) +
                     " of " + std::to_string(info_.header_frames) +
                     " frames present; copy the file again");
  }
  if (frames_read_ < 2) {
    throw InputError(info_.path.string() + ": holds " + std::to_string(frames_read_) +
                     " sample(s); a recording needs at least 2");
  }
  return false;
}

Recording LoadRecording(const std::filesystem::path& path, int channel) {
  RecordingReader reader(path);
  if (channel < 0 || channel >= reader.info().channel_count) {
    throw ConfigError("channel " + std::to_string(channel) + " does not exist in " + path.string() +
                      ", which has channels 0.." + std::to_string(reader.info().channel_count - 1));
  }
  Recording recording;
  recording.source_path = path;
  recording.sample_rate_hz = reader.info().sample_rate_hz;
  recording.source_channel = channel;
  recording.source_channel_count = reader.info().channel_count;
  std::vector<std::vector<float>> block;
  while (reader.ReadBlock(block, 1 << 16)) {
    const auto& samples = block[static_cast<size_t>(channel)];
    recording.samples.insert(recording.samples.end(), samples.begin(), samples.end());
  }
  return recording;
}

}  // namespace bouncecal::audio
