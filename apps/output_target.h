#ifndef BOUNCECAL_APPS_OUTPUT_TARGET_H_
#define BOUNCECAL_APPS_OUTPUT_TARGET_H_

#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

namespace bouncecal::apps {

// "-" as an output path names standard output, for every text output (JSON, CSV, HTML).
bool IsStdout(const std::filesystem::path& path);

// The text outputs of one run, by option name. At most one may be "-": two documents on one
// stream could not be told apart, so a second one is a ConfigError naming both options.
class TextOutputs {
 public:
  TextOutputs(
      std::initializer_list<std::pair<std::string_view, const std::filesystem::path*>> outputs);
  // True when one of the outputs is "-": tables and notes then go to stderr.
  bool stdout_taken() const { return stdout_taken_; }
  // Where the human-readable table and messages go: stdout, or stderr when a document takes
  // stdout, so `--json - | jq` reads JSON only.
  std::FILE* human() const { return stdout_taken_ ? stderr : stdout; }

 private:
  bool stdout_taken_ = false;
};

// Writes a finished text document: to standard output for "-" (OutputError when it cannot be
// written, e.g. a closed pipe), else atomically to the file (bouncecal::WriteFileAtomically).
void WriteTextOutput(const std::filesystem::path& path, const std::string& content);

// ConfigError naming the option unless the file's extension (any case) is one of `extensions`
// (with the dot): where an output has a choice of formats, or is binary, the name chooses the
// format, and a name that chooses none ("x.mp3", "-") is refused. `what` says what is written,
// e.g. "synth writes WAV or FLAC".
void CheckOutputExtension(std::string_view option, const std::filesystem::path& path,
                          std::initializer_list<std::string_view> extensions,
                          std::string_view what);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_OUTPUT_TARGET_H_
