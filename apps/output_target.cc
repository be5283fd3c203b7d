#include "output_target.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>

#include "bouncecal/atomic_file.h"
#include "bouncecal/error.h"

namespace bouncecal::apps {

bool IsStdout(const std::filesystem::path& path) { return path == "-"; }

TextOutputs::TextOutputs(
    std::initializer_list<std::pair<std::string_view, const std::filesystem::path*>> outputs) {
  std::string_view first;
  for (const auto& [option, path] : outputs) {
    if (!IsStdout(*path)) continue;
    if (stdout_taken_) {
      throw ConfigError(fmt::format(
          "{} - and {} - would both write to standard output; send one of them to a file", first,
          option));
    }
    stdout_taken_ = true;
    first = option;
  }
}

void WriteTextOutput(const std::filesystem::path& path, const std::string& content) {
  if (!IsStdout(path)) {
    WriteFileAtomically(path, content);
    return;
  }
  // The table printed before went through the same stdio buffer; flushing once at the end keeps
  // the document whole.
  if (std::fwrite(content.data(), 1, content.size(), stdout) != content.size() ||
      std::fflush(stdout) != 0) {
    throw OutputError("writing to standard output failed (a closed pipe?); nothing more to do");
  }
}

void CheckOutputExtension(std::string_view option, const std::filesystem::path& path,
                          std::initializer_list<std::string_view> extensions,
                          std::string_view what) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) return;
  std::string list;
  std::size_t index = 0;
  for (const auto& allowed : extensions) {
    if (index > 0) list += index + 1 == extensions.size() ? " or " : ", ";
    list += allowed;
    ++index;
  }
  throw ConfigError(
      fmt::format("{} '{}': {}; end the file name in {}", option, path.string(), what, list));
}

}  // namespace bouncecal::apps
