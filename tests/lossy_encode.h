#ifndef BOUNCECAL_TESTS_LOSSY_ENCODE_H_
#define BOUNCECAL_TESTS_LOSSY_ENCODE_H_

// Encodes recordings with Debian's `ffmpeg` command, as a phone or an export would: for the codec
// tests and bench/codec_timing_bench. The command is optional (scripts/install_deps.sh installs
// it); callers skip with FfmpegMissingMessage() when it is absent.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace bouncecal::testing {

// One encoder setting: a codec family ("aac", "mp3", "vorbis", "opus", "g711", "adpcm"), a label
// for tables, the
// file extension that picks the container, and ffmpeg's output options.
struct LossyEncoding {
  std::string family;
  std::string label;
  std::string extension;
  std::vector<std::string> ffmpeg_options;
};

// The settings bench/codec_timing_bench measures (docs/codecs.md): phone and export bit rates of
// Debian's encoders (FFmpeg's native AAC, LAME, libvorbis, libopus, and its G.711 and ADPCM).
inline std::vector<LossyEncoding> CommonLossyEncodings() {
  return {
      {"aac", "AAC 64k", "m4a", {"-c:a", "aac", "-b:a", "64k"}},
      {"aac", "AAC 128k", "m4a", {"-c:a", "aac", "-b:a", "128k"}},
      {"mp3", "MP3 64k", "mp3", {"-c:a", "libmp3lame", "-b:a", "64k"}},
      {"mp3", "MP3 128k", "mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}},
      {"mp3", "MP3 192k", "mp3", {"-c:a", "libmp3lame", "-b:a", "192k"}},
      {"vorbis", "Vorbis q2", "ogg", {"-c:a", "libvorbis", "-q:a", "2"}},
      {"vorbis", "Vorbis q4", "ogg", {"-c:a", "libvorbis", "-q:a", "4"}},
      {"vorbis", "Vorbis q5", "ogg", {"-c:a", "libvorbis", "-q:a", "5"}},
      {"opus", "Opus 24k", "opus", {"-c:a", "libopus", "-b:a", "24k"}},
      {"opus", "Opus 64k", "opus", {"-c:a", "libopus", "-b:a", "64k"}},
      // Telephony's sample-by-sample codecs, in WAV as voice recorders and phone systems write
      // them: no transform block, so no pre-echo, only coarser quantisation.
      {"g711", "G.711 mu-law", "wav", {"-c:a", "pcm_mulaw"}},
      {"g711", "G.711 A-law", "wav", {"-c:a", "pcm_alaw"}},
      {"adpcm", "IMA ADPCM", "wav", {"-c:a", "adpcm_ima_wav"}},
      {"adpcm", "MS ADPCM", "wav", {"-c:a", "adpcm_ms"}},
  };
}

inline std::string ShellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

inline bool FfmpegAvailable() {
  return std::system("ffmpeg -hide_banner -loglevel quiet -version >/dev/null 2>&1") == 0;
}

inline std::string FfmpegMissingMessage() {
  return "the ffmpeg command is not installed (scripts/install_deps.sh installs it); the lossy "
         "recordings of this test cannot be encoded";
}

// Runs `ffmpeg ARGUMENTS OUTPUT` (the format from the output's extension); false when ffmpeg
// fails or writes nothing.
inline bool RunFfmpeg(const std::vector<std::string>& arguments,
                      const std::filesystem::path& output) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) about literal + temporary string.
  std::string command = "ffmpeg -nostdin -hide_banner -loglevel error -y";
  for (const auto& argument : arguments) {
    command += ' ';
    command += ShellQuoted(argument);
  }
  command += ' ';
  command += ShellQuoted(output.string());
  command += " >/dev/null 2>&1";
  return std::system(command.c_str()) == 0 && std::filesystem::exists(output);
}

// Encodes `input` into `output` (format from its extension) with the given output options;
// false when ffmpeg fails (for one, an MP3 bit rate the sample rate does not allow).
inline bool EncodeWithFfmpeg(const std::filesystem::path& input,
                             const std::filesystem::path& output,
                             const std::vector<std::string>& options) {
  std::vector<std::string> arguments = {"-i", input.string()};
  arguments.insert(arguments.end(), options.begin(), options.end());
  return RunFfmpeg(arguments, output);
}

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTS_LOSSY_ENCODE_H_
