#include "bouncecal/export/engine.h"

#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {

std::string_view ToString(Engine engine) {
  switch (engine) {
    case Engine::kLammps:
      return "lammps";
    case Engine::kLiggghts:
      return "liggghts";
  }
  return "unknown";
}

Engine EngineFromString(std::string_view name) {
  if (name == "lammps") return Engine::kLammps;
  if (name == "liggghts") return Engine::kLiggghts;
  throw ConfigError("unknown engine '" + std::string(name) +
                    "'; valid engines are: lammps, liggghts");
}

std::string_view EngineExecutable(Engine engine) {
  switch (engine) {
    case Engine::kLammps:
      return "lmp";
    case Engine::kLiggghts:
      return "liggghts";
  }
  return "unknown";
}

}  // namespace bouncecal::calibrate
