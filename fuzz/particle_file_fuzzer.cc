// Fuzzes the start-positions reader of a packing scene (insertion type "file": CSV with a header
// or a LAMMPS data file): any text must give particles with finite positions, a positive radius
// and a non-negative species, or a one-line InputError naming the file and line.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "bouncecal/error.h"
#include "scene/particle_file.h"

namespace {

// One file per fuzzing process and format, so parallel jobs (-jobs=N) do not share them.
std::filesystem::path ScratchPath(const char* extension) {
  return std::filesystem::temp_directory_path() /
         ("bouncecal_fuzz_particles_" + std::to_string(::getpid()) + extension);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the reader (by extension) and the dimension; the rest is the file.
  const bool csv = (data[0] & 1) != 0;
  const int dimension = (data[0] & 2) != 0 ? 3 : 2;
  const auto path = ScratchPath(csv ? ".csv" : ".data");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    for (const auto& p : bouncecal::dem::scene::ReadParticleFile(path, dimension)) {
      for (const double x : p.position_m) {
        if (!std::isfinite(x)) std::abort();
      }
      if (!(std::isfinite(p.radius_m) && p.radius_m > 0) || p.species < 0) std::abort();
    }
  } catch (const bouncecal::InputError& error) {
    if (std::string(error.what()).find('\n') != std::string::npos) std::abort();
  }
  // Removed after every input: libFuzzer ends at -max_total_time without a clean-up hook, and
  // each run left its two files in the temporary folder.
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  return 0;
}
