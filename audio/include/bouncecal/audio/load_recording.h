#ifndef BOUNCECAL_AUDIO_LOAD_RECORDING_H_
#define BOUNCECAL_AUDIO_LOAD_RECORDING_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/audio/recording.h"

namespace bouncecal::audio {

class AudioSource;

// Whether sample 0 of the decoded stream is the first sample the recorder captured. Lossy
// encoders prime their filter banks: the stream starts with their delay (AAC 1024-2112 samples,
// MP3 ~1105 with LAME, Opus 312 at 48 kHz), which a container states (an MP4 edit list, a LAME
// tag, the Opus pre-skip) and the decoder then drops.
enum class EncoderDelay {
  kNone,     // the codec adds none (PCM, FLAC, Vorbis in Ogg, ...)
  kRemoved,  // the file stated it and it was dropped: onsets are file times
  // The codec primes but the file does not say by how much (ADTS .aac, an MP4 without an edit
  // list, an MP3 without a LAME tag): every onset is late by the same 20-50 ms. Intervals, e_k
  // and eta_k are unaffected.
  kUnknown,
};
std::string_view ToString(EncoderDelay delay);  // "none", "removed", "unknown"

// What the header of a recording says.
struct RecordingInfo {
  std::filesystem::path path;
  int sample_rate_hz = 0;
  int channel_count = 0;
  std::int64_t header_frames = 0;  // frames the header claims; 0 when it does not say
  // Which library decodes it: "libsndfile", or "ffmpeg" for MP3 and what libsndfile cannot read.
  std::string decoder;
  // Container and codec, named as FFmpeg names them: "wav"/"pcm_s16", "flac"/"flac",
  // "ogg"/"vorbis", "mp3"/"mp3", "m4a"/"aac" (or "mp4", "3gp", "mov"), "webm"/"opus", ...
  std::string container;
  std::string codec;
  // The codec discards signal (MP3, AAC, Vorbis, Opus, mu-law, ADPCM, ...): its pre-echo and
  // band limit move onsets, which codec_timing.h accounts for.
  bool lossy = false;
  // Average bit rate of a lossy stream, all channels: the container's statement, or the file
  // size over the header's duration; unset when neither is known.
  std::optional<double> bit_rate_bps;
  EncoderDelay encoder_delay = EncoderDelay::kNone;
};

// Streams a recording in blocks so an hour of audio never has to sit in memory. Any format
// libsndfile reads (WAV PCM 16/24/32, float, FLAC, OGG Vorbis/Opus...), and MP3 and what it
// cannot through FFmpeg (M4A/AAC as phones record, WebM, CAF, AMR, ...); any rate from 8 kHz, any
// channel count; nothing is resampled and the encoder delay a container states is removed, so
// sample i sits at i / rate from the start of the recording. Every problem is an InputError with
// a one-line message naming the file: missing, empty, not audio, rate below 8 kHz or above
// 768 kHz, NaN/Inf samples, truncated or undecodable data, and (at the end of the stream) fewer
// than two samples.
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
  std::unique_ptr<AudioSource> source_;
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
