// Fuzzes the recording loader and the impact detector: any bytes, written to a file as a user's
// recorder might have left them, must either be analysed or refused with a one-line InputError;
// nothing may crash, hang, leak or read out of bounds.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "bouncecal/audio/detect_file.h"
#include "bouncecal/error.h"

namespace {

// One file per fuzzing process, so parallel jobs (-jobs=N) do not share it.
const std::filesystem::path& ScratchPath() {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("bouncecal_fuzz_" + std::to_string(::getpid()) + ".wav");
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(ScratchPath(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    bouncecal::audio::DetectImpactsInFile(ScratchPath());
  } catch (const bouncecal::InputError& error) {
    // The CLI prints the message as it is: it must stay one line.
    if (std::string(error.what()).find('\n') != std::string::npos) std::abort();
  }
  // libFuzzer ends at -max_total_time without running static destructors' clean-up: removed
  // after every input, or each run leaves its file in the temporary folder.
  std::error_code ignored;
  std::filesystem::remove(ScratchPath(), ignored);
  return 0;
}
