#ifndef BOUNCECAL_EXPORT_ENGINE_H_
#define BOUNCECAL_EXPORT_ENGINE_H_

#include <string_view>

namespace bouncecal::calibrate {

// The distributed DEM engines a calibrated material can be exported to.
enum class Engine {
  kLammps,    // LAMMPS with the GRANULAR package (Debian: lammps, executable lmp)
  kLiggghts,  // LIGGGHTS-PUBLIC 3.x (Debian: liggghts, executable liggghts)
};

std::string_view ToString(Engine engine);  // "lammps", "liggghts"
// Throws ConfigError naming the value and the valid names.
Engine EngineFromString(std::string_view name);
// The executable the Debian package installs.
std::string_view EngineExecutable(Engine engine);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_ENGINE_H_
