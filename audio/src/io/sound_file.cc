#include "io/sound_file.h"

#include <algorithm>
#include <string>
#include <utility>

#include "bouncecal/error.h"

namespace bouncecal::audio {

SoundFile SoundFile::OpenForReading(const std::filesystem::path& path) {
  std::string why_not;
  auto file = TryOpenForReading(path, &why_not);
  if (!file) {
    throw InputError(path.string() + ": not a readable audio file (" + why_not +
                     "); give a WAV, FLAC, OGG or MP3 recording");
  }
  return std::move(*file);
}

std::optional<SoundFile> SoundFile::TryOpenForReading(const std::filesystem::path& path,
                                                      std::string* why_not) {
  std::error_code ignored;
  if (!std::filesystem::exists(path, ignored)) {
    throw InputError(path.string() + ": no such file; check the path");
  }
  if (std::filesystem::is_directory(path, ignored)) {
    throw InputError(path.string() + ": is a directory, not a recording; give an audio file");
  }
  if (std::filesystem::file_size(path, ignored) == 0) {
    throw InputError(path.string() + ": file is empty; give the recording itself");
  }
  SF_INFO info{};
  SNDFILE* handle = sf_open(path.c_str(), SFM_READ, &info);
  if (handle == nullptr) {
    if (why_not) *why_not = sf_strerror(nullptr);
    return std::nullopt;
  }
  if (info.samplerate <= 0 || info.channels <= 0) {
    sf_close(handle);
    throw InputError(path.string() +
                     ": header gives no sample rate or channel count; the file "
                     "is damaged");
  }
  // Normalise integer PCM to +-1 and keep float data as stored; clipping reconstruction is not
  // our business, and libsndfile's float scaling would otherwise rescale float files.
  sf_command(handle, SFC_SET_NORM_FLOAT, nullptr, SF_TRUE);
  return SoundFile(handle, info, path);
}

SoundFile SoundFile::OpenForWriting(const std::filesystem::path& path, int sample_rate_hz,
                                    int channels, int format) {
  SF_INFO info{};
  info.samplerate = sample_rate_hz;
  info.channels = channels;
  info.format = format;
  if (!sf_format_check(&info)) {
    throw OutputError(path.string() +
                      ": libsndfile cannot write this format/rate/channel "
                      "combination; choose WAV PCM 16/24-bit or float");
  }
  SNDFILE* handle = sf_open(path.c_str(), SFM_WRITE, &info);
  if (handle == nullptr) {
    throw OutputError(path.string() + ": cannot create the audio file (" + sf_strerror(nullptr) +
                      "); check that the folder exists and is writable");
  }
  // Clip instead of wrapping when float samples exceed full scale on conversion to PCM.
  sf_command(handle, SFC_SET_CLIPPING, nullptr, SF_TRUE);
  // libsndfile's PEAK chunk of a float WAV carries the wall-clock time of writing, so the same
  // recording would differ in bytes from one second to the next; nothing reads it back.
  sf_command(handle, SFC_SET_ADD_PEAK_CHUNK, nullptr, SF_FALSE);
  return SoundFile(handle, info, path);
}

SoundFile::SoundFile(SNDFILE* handle, const SF_INFO& info, std::filesystem::path path)
    : handle_(handle), info_(info), path_(std::move(path)) {}

SoundFile::SoundFile(SoundFile&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      info_(other.info_),
      path_(std::move(other.path_)) {}

SoundFile& SoundFile::operator=(SoundFile&& other) noexcept {
  if (this != &other) {
    if (handle_ != nullptr) sf_close(handle_);
    handle_ = std::exchange(other.handle_, nullptr);
    info_ = other.info_;
    path_ = std::move(other.path_);
  }
  return *this;
}

SoundFile::~SoundFile() {
  if (handle_ != nullptr) sf_close(handle_);
}

std::string SoundFile::container_name() const {
  switch (info_.format & SF_FORMAT_TYPEMASK) {
    case SF_FORMAT_WAV:
    case SF_FORMAT_WAVEX:
      return "wav";
    case SF_FORMAT_AIFF:
      return "aiff";
    case SF_FORMAT_AU:
      return "au";
    case SF_FORMAT_W64:
      return "w64";
    case SF_FORMAT_RF64:
      return "rf64";
    case SF_FORMAT_FLAC:
      return "flac";
    case SF_FORMAT_CAF:
      return "caf";
    case SF_FORMAT_OGG:
      return "ogg";
    case SF_FORMAT_MPEG:
      return "mp3";
    default: {
      SF_FORMAT_INFO format{};
      format.format = info_.format & SF_FORMAT_TYPEMASK;
      if (sf_command(nullptr, SFC_GET_FORMAT_INFO, &format, sizeof(format)) == 0 &&
          format.extension != nullptr) {
        return format.extension;
      }
      return "unknown";
    }
  }
}

std::string SoundFile::codec_name() const {
  if ((info_.format & SF_FORMAT_TYPEMASK) == SF_FORMAT_FLAC) return "flac";
  switch (info_.format & SF_FORMAT_SUBMASK) {
    case SF_FORMAT_PCM_S8:
      return "pcm_s8";
    case SF_FORMAT_PCM_U8:
      return "pcm_u8";
    case SF_FORMAT_PCM_16:
      return "pcm_s16";
    case SF_FORMAT_PCM_24:
      return "pcm_s24";
    case SF_FORMAT_PCM_32:
      return "pcm_s32";
    case SF_FORMAT_FLOAT:
      return "pcm_f32";
    case SF_FORMAT_DOUBLE:
      return "pcm_f64";
    case SF_FORMAT_ULAW:
      return "pcm_mulaw";
    case SF_FORMAT_ALAW:
      return "pcm_alaw";
    case SF_FORMAT_IMA_ADPCM:
      return "adpcm_ima";
    case SF_FORMAT_MS_ADPCM:
      return "adpcm_ms";
    case SF_FORMAT_GSM610:
      return "gsm";
    case SF_FORMAT_VORBIS:
      return "vorbis";
    case SF_FORMAT_OPUS:
      return "opus";
    case SF_FORMAT_ALAC_16:
    case SF_FORMAT_ALAC_20:
    case SF_FORMAT_ALAC_24:
    case SF_FORMAT_ALAC_32:
      return "alac";
    case SF_FORMAT_MPEG_LAYER_I:
      return "mp1";
    case SF_FORMAT_MPEG_LAYER_II:
      return "mp2";
    case SF_FORMAT_MPEG_LAYER_III:
      return "mp3";
    default: {
      SF_FORMAT_INFO format{};
      format.format = info_.format & SF_FORMAT_SUBMASK;
      if (sf_command(nullptr, SFC_GET_FORMAT_INFO, &format, sizeof(format)) == 0 &&
          format.name != nullptr) {
        return format.name;
      }
      return "unknown";
    }
  }
}

bool SoundFile::lossy() const {
  if ((info_.format & SF_FORMAT_TYPEMASK) == SF_FORMAT_FLAC) return false;
  switch (info_.format & SF_FORMAT_SUBMASK) {
    case SF_FORMAT_PCM_S8:
    case SF_FORMAT_PCM_U8:
    case SF_FORMAT_PCM_16:
    case SF_FORMAT_PCM_24:
    case SF_FORMAT_PCM_32:
    case SF_FORMAT_FLOAT:
    case SF_FORMAT_DOUBLE:
    case SF_FORMAT_ALAC_16:
    case SF_FORMAT_ALAC_20:
    case SF_FORMAT_ALAC_24:
    case SF_FORMAT_ALAC_32:
    case SF_FORMAT_DWVW_12:
    case SF_FORMAT_DWVW_16:
    case SF_FORMAT_DWVW_24:
    case SF_FORMAT_DWVW_N:
    case SF_FORMAT_DPCM_8:
    case SF_FORMAT_DPCM_16:
      return false;
    default:
      return true;
  }
}

std::string SoundFile::LogInfo() const {
  std::string log(16384, '\0');
  sf_command(handle_, SFC_GET_LOG_INFO, log.data(), static_cast<int>(log.size()));
  log.resize(log.find('\0'));
  return log;
}

std::int64_t SoundFile::ReadFrames(std::span<float> interleaved) {
  const sf_count_t wanted = static_cast<sf_count_t>(interleaved.size()) / info_.channels;
  sf_count_t got = 0;
  if ((info_.format & SF_FORMAT_SUBMASK) == SF_FORMAT_PCM_16) {
    // 16-bit PCM, the commonest recording, as integers and scaled here in a loop that
    // vectorises (libsndfile's sample-by-sample conversion cost more than reading the file).
    // The same floats: libsndfile's normalised value is the integer times the float 2^-15, and
    // scaling by a power of two is exact.
    pcm16_.resize(interleaved.size());
    got = sf_readf_short(handle_, pcm16_.data(), wanted);
    const auto count = static_cast<std::size_t>(std::max<sf_count_t>(got, 0) * info_.channels);
    for (std::size_t i = 0; i < count; ++i) {
      interleaved[i] = static_cast<float>(pcm16_[i]) * (1.0f / 32768.0f);
    }
  } else {
    got = sf_readf_float(handle_, interleaved.data(), wanted);
  }
  if (got < 0 || (got < wanted && sf_error(handle_) != SF_ERR_NO_ERROR)) {
    throw InputError(path_.string() + ": read error (" + sf_strerror(handle_) +
                     "); the file is damaged or truncated");
  }
  return got;
}

void SoundFile::WriteFrames(std::span<const float> interleaved) {
  const sf_count_t frames = static_cast<sf_count_t>(interleaved.size()) / info_.channels;
  if (sf_writef_float(handle_, interleaved.data(), frames) != frames) {
    throw OutputError(path_.string() + ": write failed (" + sf_strerror(handle_) +
                      "); check free disk space");
  }
}

}  // namespace bouncecal::audio
