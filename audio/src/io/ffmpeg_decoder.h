#ifndef BOUNCECAL_AUDIO_SRC_IO_FFMPEG_DECODER_H_
#define BOUNCECAL_AUDIO_SRC_IO_FFMPEG_DECODER_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bouncecal/audio/load_recording.h"

namespace bouncecal::audio {

struct FfmpegLibrary;  // ffmpeg_library.h

// RAII owner of FFmpeg's demuxer, decoder and sample-format converter for one file: the only
// place that talks to libavformat/libavcodec/libswresample (loaded when the first file needs
// them, ffmpeg_library.h), for what libsndfile cannot read
// (M4A/AAC as phones record voice memos, WebM/Matroska, CAF, AMR, ...). It decodes the file's
// best audio stream at the stream's own rate and channel count, converting only the sample
// format to float, and lets libavcodec drop the encoder's priming samples the container states
// (an MP4 edit list, a LAME tag, Opus pre-skip), so sample 0 is the first sample of the
// recording. Only local files and plain media containers are opened: a playlist or a
// concatenation script that would make FFmpeg read other files or the network is refused.
//
// FFmpeg logs to stderr through a process-wide callback; library code never prints, so the first
// decoder silences FFmpeg's log if it is still at FFmpeg's default level (a host program that
// set its own level keeps it).
class FfmpegDecoder {
 public:
  // Opens the file and decodes up to its first audio frame (which fixes the output rate and
  // channel count). Returns nullptr, with the reason in *why_not, when FFmpeg does not recognise
  // the file as media or its libraries cannot be loaded; throws InputError when it does but holds
  // no audio stream (a silent video), more than one (which is the drop cannot be guessed), or a
  // stream that cannot be decoded (a damaged file, an unsupported codec).
  static std::unique_ptr<FfmpegDecoder> Open(const std::filesystem::path& path,
                                             std::string* why_not);

  FfmpegDecoder(const FfmpegDecoder&) = delete;
  FfmpegDecoder& operator=(const FfmpegDecoder&) = delete;
  ~FfmpegDecoder();

  int sample_rate_hz() const { return sample_rate_hz_; }
  int channels() const { return channels_; }
  // The demuxer's name, the one of its names the file's extension gives ("m4a", "mp4", "3gp",
  // "webm", "mkv" is "matroska", "ogg", "mp3", "aac" for ADTS, ...), and libavcodec's codec name
  // ("aac", "mp3", "opus", "vorbis", "pcm_s16le", ...).
  const std::string& container() const { return container_; }
  const std::string& codec() const { return codec_; }
  bool lossy() const { return lossy_; }
  // The stream's average bit rate as the container states it, or unset.
  std::optional<double> bit_rate_bps() const { return bit_rate_bps_; }
  EncoderDelay encoder_delay() const { return encoder_delay_; }

  // Reads up to interleaved.size() / channels() frames as float; returns the number read, 0 at
  // the end. Throws InputError for a packet that cannot be read or decoded (a frame dropped in
  // the middle would move every later onset), or a stream that changes its rate or channel
  // count, or (at the end) a stream well short of the length its header states.
  std::int64_t ReadFrames(std::span<float> interleaved);

 private:
  struct Handles;
  FfmpegDecoder(const std::filesystem::path& path, const FfmpegLibrary& av);
  // Decodes the next frame of the stream into pending_; false at the end of the stream.
  bool DecodeNextFrame();
  void ConvertFrame();
  // Throws InputError when the stream ended well short of the length its header states.
  void CheckLength() const;
  [[noreturn]] void Damaged(const std::string& what, int av_error) const;

  std::filesystem::path path_;
  const FfmpegLibrary* av_;
  std::unique_ptr<Handles> handles_;
  int stream_index_ = -1;
  int sample_rate_hz_ = 0;
  int channels_ = 0;
  std::string container_;
  std::string codec_;
  bool lossy_ = false;
  std::optional<double> bit_rate_bps_;
  EncoderDelay encoder_delay_ = EncoderDelay::kNone;
  bool codec_primes_ = false;
  bool delay_stated_ = false;
  bool flushed_ = false;
  bool finished_ = false;
  std::int64_t frames_decoded_ = 0;
  std::int64_t promised_frames_ = 0;  // the header's length in output frames; 0: none stated
  std::vector<float> pending_;        // converted samples of the last frame, interleaved
  std::size_t pending_offset_ = 0;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_IO_FFMPEG_DECODER_H_
