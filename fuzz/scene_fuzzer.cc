// Fuzzes the packing-scene parser (dem::SceneFromJson, its strict JsonReader and the inline
// contact law): any JSON text must become a scene or a one-line InputError; any other exception,
// a crash, a leak or undefined behaviour is a finding. A scene that parses must also be one the
// packing code can size safely (a finite positive diameter, a count within the refused-memory
// limit), since `bouncecal pack` allocates from these numbers before simulating anything.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  try {
    // A folder that does not exist: material_card and insertion paths resolve into it, so the
    // fuzzer never reads a real file by a relative path.
    const auto scene =
        bouncecal::dem::SceneFromJson(json, "/nonexistent/bouncecal_fuzz/scene.json");
    const double diameter_m = scene.particles.diameter.MaxDiameterM();
    if (!(std::isfinite(diameter_m) && diameter_m > 0) || scene.particles.count < 1 ||
        scene.particles.count > bouncecal::dem::kMaxSceneParticles || !(scene.time_step_s > 0) ||
        scene.particles.species.empty()) {
      std::abort();
    }
  } catch (const bouncecal::InputError& error) {
    if (std::string(error.what()).find('\n') != std::string::npos) std::abort();
  }
  return 0;
}
