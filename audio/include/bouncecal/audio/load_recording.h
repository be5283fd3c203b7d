#ifndef BOUNCECAL_AUDIO_LOAD_RECORDING_H_
#define BOUNCECAL_AUDIO_LOAD_RECORDING_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "bouncecal/audio/recording.h"

namespace bouncecal::audio {

class SoundFile;

// What the header of a recording says.
struct RecordingInfo {
  std::filesystem::path path;
  int sample_rate_hz = 0;
  int channel_count = 0;
  std::int64_t header_frames = 0;  // frames the header claims
};

// Streams a recording in blocks so an hour of audio never has to sit in memory. Any format
// libsndfile reads (WAV PCM 16/24/32, float, FLAC, OGG...), any rate from 8 kHz, any channel
// count; nothing is resampled. Every problem is an InputError with a one-line message naming the
// file: missing, empty, not audio, rate below 8 kHz or above 768 kHz, NaN/Inf samples, truncated
// data, and (at the end of the stream) fewer than two samples.
class RecordingReader {
 public:
  static constexpr int kMinSampleRateHz = 8000;
  static constexpr int kMaxSampleRateHz = 768000;

  explicit RecordingReader(const std::filesystem::path& path);
  RecordingReader(RecordingReader&&) noexcept;
  RecordingReader& operator=(RecordingReader&&) noexcept;
  ~RecordingReader();

  const RecordingInfo& info() const { return info_; }
  // Reads up to max_frames frames into one vector per channel (resized to the frames read).
  // Returns false, with empty channels, at the end of the data.
  bool ReadBlock(std::vector<std::vector<float>>& channels, std::size_t max_frames);
  std::int64_t frames_read() const { return frames_read_; }

 private:
  std::unique_ptr<SoundFile> file_;
  RecordingInfo info_;
  std::vector<float> interleaved_;
  std::int64_t frames_read_ = 0;
  bool finished_ = false;
};

// Loads one channel (0-based) of a recording into memory: for short files, tests and tools.
// Throws InputError for unreadable files and ConfigError for a channel the file does not have.
Recording LoadRecording(const std::filesystem::path& path, int channel = 0);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_LOAD_RECORDING_H_
