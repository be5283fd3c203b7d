#include "io/audio_source.h"

#include <cmath>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include "bouncecal/error.h"
#include "io/ffmpeg_decoder.h"
#include "io/sound_file.h"

namespace bouncecal::audio {
namespace {

// What the refusal of an unreadable file lists.
constexpr const char* kReadableFormats =
    "give a WAV, FLAC, OGG (Vorbis, Opus), MP3, M4A/AAC, WebM or CAF recording";

// An ID3 tag or an MPEG audio frame sync (11 set bits), which is how libsndfile recognises an
// MP3 too.
bool LooksLikeMpegAudio(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char head[3] = {};
  if (!in.read(reinterpret_cast<char*>(head), sizeof(head))) return false;
  return (head[0] == 'I' && head[1] == 'D' && head[2] == '3') ||
         (head[0] == 0xff && (head[1] & 0xe0) == 0xe0);
}

bool IsMpegAudio(const std::string& codec) {
  return codec == "mp1" || codec == "mp2" || codec == "mp3";
}

class SndfileSource final : public AudioSource {
 public:
  SndfileSource(const std::filesystem::path& path, SoundFile file) : file_(std::move(file)) {
    info_.path = path;
    info_.sample_rate_hz = file_.sample_rate_hz();
    info_.channel_count = file_.channels();
    info_.header_frames = file_.frames();
    info_.decoder = "libsndfile";
    info_.container = file_.container_name();
    info_.codec = file_.codec_name();
    info_.lossy = file_.lossy();
    // libsndfile shortens the frame count of a WAV whose data chunk runs past the end of the
    // file and notes "data : N (should be M)" in its log; that is a truncated copy.
    const std::string log = file_.LogInfo();
    const auto data_line = log.find("data : ");
    if (data_line != std::string::npos &&
        log.substr(data_line, log.find('\n', data_line) - data_line).find("should be") !=
            std::string::npos) {
      throw InputError(path.string() +
                       ": truncated (the data chunk is shorter than its header says); copy or "
                       "export the file again");
    }
    if (info_.lossy) {
      std::error_code error;
      const auto bytes = std::filesystem::file_size(path, error);
      if (!error && info_.header_frames > 0 && info_.sample_rate_hz > 0) {
        info_.bit_rate_bps = std::round(8.0 * static_cast<double>(bytes) * info_.sample_rate_hz /
                                        static_cast<double>(info_.header_frames));
      }
    }
    info_.encoder_delay = EncoderDelayOf(path);
    // Without a LAME/Info tag (the one that states the delay), an MP3's length is estimated from
    // its size and first frame; a whole CBR file then decodes to a few hundred frames fewer,
    // which is no truncation.
    if (info_.container == "mp3" && info_.encoder_delay != EncoderDelay::kRemoved) {
      info_.header_frames = 0;
    }
  }

  const RecordingInfo& info() const override { return info_; }
  std::int64_t ReadFrames(std::span<float> interleaved) override {
    return file_.ReadFrames(interleaved);
  }

 private:
  EncoderDelay EncoderDelayOf(const std::filesystem::path& path) const {
    // An Ogg Opus header always carries the pre-skip, which libsndfile drops.
    if (info_.codec == "opus") return EncoderDelay::kRemoved;
    // mpg123 (libsndfile's MP3 decoder) drops the delay a LAME/Info tag states, as FFmpeg does;
    // FFmpeg's demuxer tells whether the file has one.
    if (IsMpegAudio(info_.codec)) {
      try {
        const auto probe = FfmpegDecoder::Open(path, nullptr);
        return probe ? probe->encoder_delay() : EncoderDelay::kUnknown;
      } catch (const InputError&) {
        return EncoderDelay::kUnknown;
      }
    }
    return EncoderDelay::kNone;
  }

  SoundFile file_;
  RecordingInfo info_;
};

class FfmpegSource final : public AudioSource {
 public:
  FfmpegSource(const std::filesystem::path& path, std::unique_ptr<FfmpegDecoder> decoder)
      : decoder_(std::move(decoder)) {
    info_.path = path;
    info_.sample_rate_hz = decoder_->sample_rate_hz();
    info_.channel_count = decoder_->channels();
    // Container durations are estimates for several formats (an MP3 or ADTS stream's comes from
    // its size), so no frame count is promised and the truncation check is the decoder's.
    info_.header_frames = 0;
    info_.decoder = "ffmpeg";
    info_.container = decoder_->container();
    info_.codec = decoder_->codec();
    info_.lossy = decoder_->lossy();
    if (info_.lossy) info_.bit_rate_bps = decoder_->bit_rate_bps();
    info_.encoder_delay = decoder_->encoder_delay();
  }

  const RecordingInfo& info() const override { return info_; }
  std::int64_t ReadFrames(std::span<float> interleaved) override {
    return decoder_->ReadFrames(interleaved);
  }

 private:
  std::unique_ptr<FfmpegDecoder> decoder_;
  RecordingInfo info_;
};

}  // namespace

std::unique_ptr<AudioSource> OpenAudioSource(const std::filesystem::path& path) {
  // libsndfile's MPEG decoder (mpg123) resyncs past a damaged frame without a word to the caller
  // (a dropped frame moves every later onset) and prints its notes to stderr, even while
  // sf_open parses the header; FFmpeg's refuses the frame. So what starts like MPEG audio goes
  // to FFmpeg only (libsndfile recognises MPEG by the same start), and libsndfile keeps an MPEG
  // file FFmpeg cannot open only if it starts otherwise.
  if (LooksLikeMpegAudio(path)) {
    std::string ffmpeg_reason;
    if (auto decoder = FfmpegDecoder::Open(path, &ffmpeg_reason)) {
      return std::make_unique<FfmpegSource>(path, std::move(decoder));
    }
    throw InputError(path.string() + ": not a readable audio file (it starts like MP3, but " +
                     "FFmpeg: " + ffmpeg_reason + "); " + kReadableFormats);
  }
  std::string sndfile_reason;
  auto file = SoundFile::TryOpenForReading(path, &sndfile_reason);
  if (file) {
    if (IsMpegAudio(file->codec_name())) {
      if (auto decoder = FfmpegDecoder::Open(path, nullptr)) {
        return std::make_unique<FfmpegSource>(path, std::move(decoder));
      }
    }
    return std::make_unique<SndfileSource>(path, std::move(*file));
  }
  std::string ffmpeg_reason;
  auto decoder = FfmpegDecoder::Open(path, &ffmpeg_reason);
  if (decoder) return std::make_unique<FfmpegSource>(path, std::move(decoder));
  throw InputError(path.string() + ": not a readable audio file (libsndfile: " + sndfile_reason +
                   " FFmpeg: " + ffmpeg_reason + "); " + kReadableFormats);
}

}  // namespace bouncecal::audio
