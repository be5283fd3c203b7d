#ifndef BOUNCECAL_AUDIO_SRC_IO_SOUND_FILE_H_
#define BOUNCECAL_AUDIO_SRC_IO_SOUND_FILE_H_

#include <sndfile.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bouncecal::audio {

// RAII owner of a libsndfile handle: the only place that talks to libsndfile, so every error
// message names the file and says what to do.
class SoundFile {
 public:
  // Opens for reading; throws InputError (missing file, directory, not audio, unsupported codec).
  static SoundFile OpenForReading(const std::filesystem::path& path);
  // The same, but a file libsndfile does not recognise gives nullopt and libsndfile's reason in
  // *why_not (another decoder may read it); a missing, empty or directory path still throws.
  static std::optional<SoundFile> TryOpenForReading(const std::filesystem::path& path,
                                                    std::string* why_not);
  // Opens for writing with a libsndfile format such as SF_FORMAT_WAV | SF_FORMAT_PCM_16.
  static SoundFile OpenForWriting(const std::filesystem::path& path, int sample_rate_hz,
                                  int channels, int format);

  SoundFile(SoundFile&& other) noexcept;
  SoundFile& operator=(SoundFile&& other) noexcept;
  SoundFile(const SoundFile&) = delete;
  SoundFile& operator=(const SoundFile&) = delete;
  ~SoundFile();

  int sample_rate_hz() const { return info_.samplerate; }
  int channels() const { return info_.channels; }
  // Frames the header claims; a truncated file may hold fewer, so readers must trust the count
  // ReadFrames returns, not this.
  std::int64_t frames() const { return info_.frames; }
  int format() const { return info_.format; }
  // The format in FFmpeg's vocabulary, so both decoders name codecs alike: container "wav",
  // "flac", "ogg", "mp3", ...; codec "pcm_s16", "pcm_f32", "flac", "vorbis", "opus", "mp3", ...
  std::string container_name() const;
  std::string codec_name() const;
  // Whether the codec discards signal: everything but PCM, float, FLAC, ALAC and the lossless
  // delta codings (DWVW, DPCM).
  bool lossy() const;
  const std::filesystem::path& path() const { return path_; }
  // libsndfile's parse log of the header (used to spot a data chunk longer than the file).
  std::string LogInfo() const;

  // Reads up to interleaved.size() / channels() frames as float (full scale +-1); returns the
  // number of frames read, 0 at the end. Throws InputError on a read error.
  std::int64_t ReadFrames(std::span<float> interleaved);
  // Writes whole frames; throws OutputError on failure.
  void WriteFrames(std::span<const float> interleaved);

 private:
  SoundFile(SNDFILE* handle, const SF_INFO& info, std::filesystem::path path);

  SNDFILE* handle_ = nullptr;
  SF_INFO info_{};
  std::filesystem::path path_;
  std::vector<short> pcm16_;  // ReadFrames' integer block for 16-bit PCM
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_IO_SOUND_FILE_H_
