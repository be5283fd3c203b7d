#include "sound_file.h"

#include <string>
#include <utility>

#include "bouncecal/error.h"

namespace bouncecal::audio {

SoundFile SoundFile::OpenForReading(const std::filesystem::path& path) {
  std::error_code ignored;
  if (!std::filesystem::exists(path, ignored)) {
    throw InputError(path.string() + ": no such file; check the path");
  }
  if (std::filesystem::is_directory(path, ignored)) {
    throw InputError(path.string() + ": is a directory, not a recording; give an audio file");
  }
  if (std::filesystem::file_size(path, ignored) == 0) {
    throw InputError(path.string() + ": file is empty; give a WAV/FLAC/OGG recording");
  }
  SF_INFO info{};
  SNDFILE* handle = sf_open(path.c_str(), SFM_READ, &info);
  if (handle == nullptr) {
    throw InputError(path.string() + ": not a readable audio file (" + sf_strerror(nullptr) +
                     "); give a WAV, FLAC or OGG recording");
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
  // libsndfile adds a PEAK chunk to float files by default, and that chunk carries the time of
  // writing: the same seed would give different bytes a second later (issue 7: byte-identical
  // output). The peak is not needed to read the file back.
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

std::string SoundFile::LogInfo() const {
  std::string log(16384, '\0');
  sf_command(handle_, SFC_GET_LOG_INFO, log.data(), static_cast<int>(log.size()));
  log.resize(log.find('\0'));
  return log;
}

std::int64_t SoundFile::ReadFrames(std::span<float> interleaved) {
  const sf_count_t wanted = static_cast<sf_count_t>(interleaved.size()) / info_.channels;
  const sf_count_t got = sf_readf_float(handle_, interleaved.data(), wanted);
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
