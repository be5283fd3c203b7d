#include "io/ffmpeg_decoder.h"

extern "C" {
#include <libavutil/channel_layout.h>
#include <libavutil/intreadwrite.h>
}

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <mutex>
#include <string_view>

#include "bouncecal/error.h"
#include "io/ffmpeg_library.h"

namespace bouncecal::audio {
namespace {

// Demuxers of self-contained media files. Everything else FFmpeg probes is left out on purpose:
// playlists and scripts (hls, dash, concat, ffmetadata, sdp) open further files or the network,
// image and subtitle demuxers hold no audio, and raw PCM has no header to check.
constexpr const char* kContainers =
    "mov,mp4,m4a,3gp,3g2,mj2,matroska,webm,ogg,mp3,aac,loas,latm,wav,w64,rf64,flac,caf,aiff,"
    "asf,avi,amr,amrnb,amrwb,wv,ape,tta,tak,ac3,eac3,dts,dtshd,truehd,mlp,au,voc,mpc,mpc8,shn,"
    "oma,dsf,flv,mpegts,mpeg,wsd,xwma,qcp,gsm,sbc,ircam,nistsphere,sox,rm,mmf";

// Codecs whose encoder delays the signal by priming samples that a container should state: an
// onset read from such a stream without that statement is late by the encoder's delay.
constexpr std::string_view kPrimingCodecs[] = {"aac",   "aac_latm", "mp1",    "mp2",
                                               "mp3",   "opus",     "ac3",    "eac3",
                                               "wmav1", "wmav2",    "wmapro", "speex"};

std::string AvError(const FfmpegLibrary& av, int error) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av.av_strerror(error, text, sizeof(text));
  return text;
}

// A demuxer serves several formats ("mov,mp4,m4a,3gp,3g2,mj2", "matroska,webm"): the one the
// file's extension names, else the first.
std::string ContainerName(std::string_view names, const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string first;
  for (std::size_t start = 0; start <= names.size();) {
    const std::size_t end = std::min(names.find(',', start), names.size());
    const std::string name(names.substr(start, end - start));
    if (first.empty()) first = name;
    if (!extension.empty() && name == extension) return name;
    start = end + 1;
  }
  return first;
}

void SilenceFfmpegLog(const FfmpegLibrary& av) {
  static std::once_flag once;
  std::call_once(once, [&av] {
    if (av.av_log_get_level() == AV_LOG_INFO) av.av_log_set_level(AV_LOG_QUIET);
  });
}

}  // namespace

struct FfmpegDecoder::Handles {
  explicit Handles(const FfmpegLibrary& av) : library(&av) {}
  const FfmpegLibrary* library;
  struct FormatDeleter {
    const FfmpegLibrary* av;
    void operator()(AVFormatContext* context) const { av->avformat_close_input(&context); }
  };
  struct CodecDeleter {
    const FfmpegLibrary* av;
    void operator()(AVCodecContext* context) const { av->avcodec_free_context(&context); }
  };
  struct ResamplerDeleter {
    const FfmpegLibrary* av;
    void operator()(SwrContext* context) const { av->swr_free(&context); }
  };
  struct PacketDeleter {
    const FfmpegLibrary* av;
    void operator()(AVPacket* packet) const { av->av_packet_free(&packet); }
  };
  struct FrameDeleter {
    const FfmpegLibrary* av;
    void operator()(AVFrame* frame) const { av->av_frame_free(&frame); }
  };
  std::unique_ptr<AVFormatContext, FormatDeleter> format{nullptr, {library}};
  std::unique_ptr<AVCodecContext, CodecDeleter> codec{nullptr, {library}};
  std::unique_ptr<SwrContext, ResamplerDeleter> converter{nullptr, {library}};
  std::unique_ptr<AVPacket, PacketDeleter> packet{library->av_packet_alloc(), {library}};
  std::unique_ptr<AVFrame, FrameDeleter> frame{library->av_frame_alloc(), {library}};
  int converter_format = -1;  // the AVSampleFormat the converter was made for
};

FfmpegDecoder::FfmpegDecoder(const std::filesystem::path& path, const FfmpegLibrary& av)
    : path_(path), av_(&av), handles_(std::make_unique<Handles>(av)) {}

FfmpegDecoder::~FfmpegDecoder() = default;

void FfmpegDecoder::Damaged(const std::string& what, int av_error) const {
  char at[32] = "the start";
  if (sample_rate_hz_ > 0) {
    std::snprintf(at, sizeof(at), "%.3f s", static_cast<double>(frames_decoded_) / sample_rate_hz_);
  }
  throw InputError(path_.string() + ": " + what + " near " + at + " (" + AvError(*av_, av_error) +
                   "); the file is damaged or truncated, copy or export it again");
}

std::unique_ptr<FfmpegDecoder> FfmpegDecoder::Open(const std::filesystem::path& path,
                                                   std::string* why_not) {
  const FfmpegLibrary* library = LoadFfmpeg(why_not);
  if (library == nullptr) return nullptr;
  const FfmpegLibrary& av = *library;
  SilenceFfmpegLog(av);
  std::unique_ptr<FfmpegDecoder> decoder(new FfmpegDecoder(path, av));
  Handles& h = *decoder->handles_;
  if (!h.packet || !h.frame) throw InputError(path.string() + ": out of memory opening it");

  AVDictionary* options = nullptr;
  av.av_dict_set(&options, "protocol_whitelist", "file", 0);
  av.av_dict_set(&options, "format_whitelist", kContainers, 0);
  AVFormatContext* format = nullptr;
  // "file:" keeps a colon in the user's path from being read as a protocol name.
  const std::string url = "file:" + path.string();
  const int opened = av.avformat_open_input(&format, url.c_str(), nullptr, &options);
  av.av_dict_free(&options);
  if (opened < 0) {
    // EINVAL: the probe found a format outside kContainers.
    if (why_not) {
      *why_not = opened == AVERROR(EINVAL)
                     ? std::string("a playlist, script or other format that holds no recording")
                     : AvError(av, opened);
    }
    return nullptr;
  }
  h.format.reset(format);
  const int found = av.avformat_find_stream_info(format, nullptr);
  if (found < 0) {
    if (why_not) *why_not = AvError(av, found);
    return nullptr;
  }
  const std::string container = ContainerName(format->iformat->name, path);
  unsigned audio_streams = 0;
  for (unsigned i = 0; i < format->nb_streams; ++i) {
    if (format->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_AUDIO) ++audio_streams;
  }
  // FFmpeg recognised the file, so its own words are the clearer refusal than "not audio".
  if (audio_streams == 0) {
    throw InputError(path.string() + ": " + container +
                     " file without an audio stream (a video recorded without sound?); give a "
                     "file that holds the recording");
  }
  // Which of two microphones or languages is the drop cannot be guessed, and a guess that
  // happened to pick the wrong one would be analysed without complaint.
  if (audio_streams > 1) {
    throw InputError(path.string() + ": holds " + std::to_string(audio_streams) +
                     " audio streams and which one is the drop is unclear; extract it, e.g. "
                     "ffmpeg -i FILE -map 0:a:0 drop.wav");
  }
  const int stream = av.av_find_best_stream(format, AVMEDIA_TYPE_AUDIO, -1, -1, nullptr, 0);
  if (stream < 0) {
    throw InputError(path.string() + ": its audio stream cannot be decoded by this FFmpeg (" +
                     AvError(av, stream) + "); convert it to WAV or FLAC");
  }
  const AVStream* audio = format->streams[stream];
  const std::string codec_name = av.avcodec_get_name(audio->codecpar->codec_id);
  const AVCodec* codec = av.avcodec_find_decoder(audio->codecpar->codec_id);
  if (codec == nullptr) {
    throw InputError(path.string() + ": its " + codec_name +
                     " audio cannot be decoded by this FFmpeg; convert it to WAV or FLAC");
  }
  decoder->stream_index_ = stream;
  for (unsigned i = 0; i < format->nb_streams; ++i) {
    if (static_cast<int>(i) != stream) format->streams[i]->discard = AVDISCARD_ALL;
  }
  decoder->container_ = container;
  decoder->codec_ = codec_name;
  const AVCodecDescriptor* descriptor = av.avcodec_descriptor_get(audio->codecpar->codec_id);
  // A codec FFmpeg does not call lossless is treated as lossy: wider uncertainties are the safe
  // side.
  decoder->lossy_ = descriptor == nullptr || (descriptor->props & AV_CODEC_PROP_LOSSLESS) == 0;
  if (audio->codecpar->bit_rate > 0) {
    decoder->bit_rate_bps_ = static_cast<double>(audio->codecpar->bit_rate);
  } else if (format->nb_streams == 1 && format->bit_rate > 0) {
    decoder->bit_rate_bps_ = static_cast<double>(format->bit_rate);
  }
  decoder->codec_primes_ = std::find(std::begin(kPrimingCodecs), std::end(kPrimingCodecs),
                                     codec_name) != std::end(kPrimingCodecs);
  // Every Opus header carries its pre-skip, which libavcodec's decoder drops itself (Matroska
  // also states it as the codec delay).
  decoder->delay_stated_ = codec_name == "opus" || audio->codecpar->initial_padding > 0;

  h.codec.reset(av.avcodec_alloc_context3(codec));
  if (!h.codec) throw InputError(path.string() + ": out of memory opening its decoder");
  int status = av.avcodec_parameters_to_context(h.codec.get(), audio->codecpar);
  if (status >= 0) {
    h.codec->pkt_timebase = audio->time_base;
    // One thread: decoding stays deterministic and the shared cores stay free.
    h.codec->thread_count = 1;
    status = av.avcodec_open2(h.codec.get(), codec, nullptr);
  }
  if (status < 0) {
    throw InputError(path.string() + ": cannot open its " + codec_name + " decoder (" +
                     AvError(av, status) + "); convert it to WAV or FLAC");
  }
  // The first frame fixes the output: HE-AAC, for one, decodes at twice the rate its stream
  // header gives.
  if (!decoder->DecodeNextFrame()) {
    throw InputError(path.string() + ": its " + codec_name +
                     " audio stream holds no decodable sample; the file is damaged or empty");
  }
  // A length the container states in its header (an MP4 sample table, a Xing/LAME frame count,
  // Matroska's duration) is a promise a cut copy breaks without a damaged packet when the cut
  // falls between frames; a length estimated from the file size or read from the last page
  // (an MP3 without tag, ADTS, Ogg) promises nothing.
  if (format->duration_estimation_method == AVFMT_DURATION_FROM_STREAM &&
      audio->duration != AV_NOPTS_VALUE && audio->duration > 0 &&
      std::string_view(format->iformat->name) != "ogg") {
    decoder->promised_frames_ =
        av.av_rescale_q(audio->duration, audio->time_base, AVRational{1, decoder->sample_rate_hz_});
  }
  decoder->encoder_delay_ = !decoder->codec_primes_  ? EncoderDelay::kNone
                            : decoder->delay_stated_ ? EncoderDelay::kRemoved
                                                     : EncoderDelay::kUnknown;
  return decoder;
}

bool FfmpegDecoder::DecodeNextFrame() {
  const FfmpegLibrary& av = *av_;
  Handles& h = *handles_;
  while (true) {
    int status = av.avcodec_receive_frame(h.codec.get(), h.frame.get());
    if (status == 0) {
      const bool corrupt = (h.frame->flags & AV_FRAME_FLAG_CORRUPT) != 0;
      if (corrupt) Damaged("a corrupt frame", AVERROR_INVALIDDATA);
      ConvertFrame();
      av.av_frame_unref(h.frame.get());
      if (pending_.empty()) continue;  // a frame that was all priming
      return true;
    }
    if (status == AVERROR_EOF) return false;
    if (status != AVERROR(EAGAIN)) Damaged("a frame that cannot be decoded", status);
    if (flushed_) return false;
    status = av.av_read_frame(h.format.get(), h.packet.get());
    if (status == AVERROR_EOF) {
      flushed_ = true;
      status = av.avcodec_send_packet(h.codec.get(), nullptr);
      if (status < 0 && status != AVERROR_EOF) Damaged("the end of the stream", status);
      continue;
    }
    if (status < 0) Damaged("a packet that cannot be read", status);
    if (h.packet->stream_index != stream_index_) {
      av.av_packet_unref(h.packet.get());
      continue;
    }
    if ((h.packet->flags & AV_PKT_FLAG_CORRUPT) != 0) {
      av.av_packet_unref(h.packet.get());
      Damaged("a corrupt packet (audio lost in recording or transfer)", AVERROR_INVALIDDATA);
    }
    std::size_t side_size = 0;
    const std::uint8_t* skip =
        av.av_packet_get_side_data(h.packet.get(), AV_PKT_DATA_SKIP_SAMPLES, &side_size);
    if (skip != nullptr && side_size >= 4 && AV_RL32(skip) > 0) delay_stated_ = true;
    status = av.avcodec_send_packet(h.codec.get(), h.packet.get());
    av.av_packet_unref(h.packet.get());
    if (status < 0 && status != AVERROR(EAGAIN)) {
      Damaged("a packet that cannot be decoded", status);
    }
  }
}

void FfmpegDecoder::ConvertFrame() {
  const FfmpegLibrary& av = *av_;
  Handles& h = *handles_;
  // Not const: FFmpeg 5.1's swr_alloc_set_opts2 takes the layouts by non-const pointer.
  AVFrame& frame = *h.frame;
  const int channels = frame.ch_layout.nb_channels;
  if (frame.sample_rate <= 0 || channels <= 0) {
    Damaged("a frame without sample rate or channels", AVERROR_INVALIDDATA);
  }
  if (sample_rate_hz_ == 0) {
    sample_rate_hz_ = frame.sample_rate;
    channels_ = channels;
  } else if (frame.sample_rate != sample_rate_hz_ || channels != channels_) {
    char at[32];
    std::snprintf(at, sizeof(at), "%.3f s", static_cast<double>(frames_decoded_) / sample_rate_hz_);
    throw InputError(path_.string() + ": the audio changes from " +
                     std::to_string(sample_rate_hz_) + " Hz, " + std::to_string(channels_) +
                     " channel(s) to " + std::to_string(frame.sample_rate) + " Hz, " +
                     std::to_string(channels) + " channel(s) at " + at +
                     "; split the file there or convert it to WAV at one rate");
  }
  if (!h.converter || h.converter_format != frame.format) {
    SwrContext* converter = nullptr;
    // Same layout and rate in and out: only the sample format changes, nothing is resampled.
    int status = av.swr_alloc_set_opts2(
        &converter, &frame.ch_layout, AV_SAMPLE_FMT_FLT, frame.sample_rate, &frame.ch_layout,
        static_cast<AVSampleFormat>(frame.format), frame.sample_rate, 0, nullptr);
    h.converter.reset(converter);
    if (status >= 0) status = av.swr_init(converter);
    if (status < 0) Damaged("samples in an unsupported format", status);
    h.converter_format = frame.format;
  }
  pending_.resize(static_cast<std::size_t>(frame.nb_samples) * static_cast<std::size_t>(channels));
  pending_offset_ = 0;
  std::uint8_t* out[] = {reinterpret_cast<std::uint8_t*>(pending_.data())};
  const int converted =
      av.swr_convert(h.converter.get(), out, frame.nb_samples,
                     const_cast<const std::uint8_t**>(frame.extended_data), frame.nb_samples);
  if (converted < 0) Damaged("samples that cannot be converted", converted);
  pending_.resize(static_cast<std::size_t>(converted) * static_cast<std::size_t>(channels));
}

void FfmpegDecoder::CheckLength() const {
  // The slack covers what a stated length and the decoded one may differ by in a whole file: the
  // rounding of a container's time base and a codec frame's worth of priming or padding (AAC's
  // 2112 samples at most).
  const std::int64_t slack = 4096;
  if (promised_frames_ > 0 && frames_decoded_ + slack < promised_frames_) {
    char lengths[96];
    std::snprintf(lengths, sizeof(lengths), "%.3f s of the %.3f s",
                  static_cast<double>(frames_decoded_) / sample_rate_hz_,
                  static_cast<double>(promised_frames_) / sample_rate_hz_);
    throw InputError(path_.string() + ": truncated, only " + lengths +
                     " its header states are present; copy or export the file again");
  }
}

std::int64_t FfmpegDecoder::ReadFrames(std::span<float> interleaved) {
  const auto channels = static_cast<std::size_t>(channels_);
  const std::size_t wanted = interleaved.size() / channels;
  std::size_t got = 0;
  while (got < wanted && !finished_) {
    if (pending_offset_ < pending_.size()) {
      const std::size_t take =
          std::min(wanted - got, (pending_.size() - pending_offset_) / channels);
      std::copy_n(pending_.begin() + static_cast<std::ptrdiff_t>(pending_offset_), take * channels,
                  interleaved.begin() + static_cast<std::ptrdiff_t>(got * channels));
      pending_offset_ += take * channels;
      got += take;
      frames_decoded_ += static_cast<std::int64_t>(take);
      continue;
    }
    if (!DecodeNextFrame()) {
      finished_ = true;
      CheckLength();
    }
  }
  return static_cast<std::int64_t>(got);
}

}  // namespace bouncecal::audio
