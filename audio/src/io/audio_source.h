#ifndef BOUNCECAL_AUDIO_SRC_IO_AUDIO_SOURCE_H_
#define BOUNCECAL_AUDIO_SRC_IO_AUDIO_SOURCE_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

#include "bouncecal/audio/load_recording.h"

namespace bouncecal::audio {

// A decoder RecordingReader streams from: libsndfile for what it reads (WAV, FLAC, OGG
// Vorbis/Opus, AIFF, ...), FFmpeg for MPEG audio and the rest (MP3, M4A/AAC, WebM, CAF, AMR, ...).
class AudioSource {
 public:
  virtual ~AudioSource() = default;
  // Path, rate, channels, the header's frame count (0 when it gives none) and the codec.
  virtual const RecordingInfo& info() const = 0;
  // Reads up to interleaved.size() / channels frames as float (full scale +-1); returns the
  // number read, 0 at the end. Throws InputError on a read or decoding error.
  virtual std::int64_t ReadFrames(std::span<float> interleaved) = 0;
};

// Opens MPEG audio with FFmpeg, anything else with libsndfile, or with FFmpeg when libsndfile
// does not recognise it. Throws
// InputError (one line naming the file) for a missing, empty or unreadable file, listing the
// formats that are read.
std::unique_ptr<AudioSource> OpenAudioSource(const std::filesystem::path& path);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_IO_AUDIO_SOURCE_H_
