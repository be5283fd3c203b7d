// The field helpers of the start-positions parsers (particle_file_parsers.h).
#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <string>

#include "bouncecal/error.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene::particle_file {

std::vector<std::string> SplitFields(const std::string& line, bool commas) {
  std::vector<std::string> fields;
  if (commas) {
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) {
      const auto b = field.find_first_not_of(" \t\r");
      const auto e = field.find_last_not_of(" \t\r");
      fields.push_back(b == std::string::npos ? "" : field.substr(b, e - b + 1));
    }
  } else {
    std::stringstream stream(line);
    std::string field;
    while (stream >> field) fields.push_back(field);
  }
  return fields;
}

std::string Where(const std::filesystem::path& path, int line) {
  return path.string() + ":" + std::to_string(line);
}

double ParseNumber(const std::string& text, const std::filesystem::path& path, int line) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) {
    throw InputError(Where(path, line) + ": '" + text +
                     "' is not a finite number; fix the particle file");
  }
  return value;
}

// Checked as a double first, since converting a double outside the integer's range is undefined
// behaviour.
std::int64_t ParseWhole(const std::string& text, const std::filesystem::path& path, int line,
                        double min, double max) {
  const double value = ParseNumber(text, path, line);
  if (value != std::floor(value) || value < min || value > max) {
    throw InputError(
        fmt::format("{}: '{}' is not a whole number in [{}, {}]; fix the particle "
                    "file",
                    Where(path, line), text, min, max));
  }
  return static_cast<std::int64_t>(value);
}

// A 2D scene moves its particles in the x-y plane: a z the file gives must be 0, or the file was
// written for a 3D scene and its particles would silently be flattened onto one another.
void RefuseZIn2d(double z, const std::filesystem::path& path, int line) {
  if (z != 0) {
    throw InputError(fmt::format(
        "{}: z = {} m in a 2D scene; 2D particles lie in the x-y plane: set z to 0 or use "
        "dimension 3",
        Where(path, line), z));
  }
}

void RefuseCount(const std::filesystem::path& path, double count, int dimension) {
  if (const auto problem = ParticleCountProblem(count, dimension)) {
    throw InputError(path.string() + ": " + *problem + "; use a file with fewer particles");
  }
}

std::string Position(const Vec3& x, int dimension) {
  return dimension == 3 ? fmt::format("({:.9g}, {:.9g}, {:.9g})", x[0], x[1], x[2])
                        : fmt::format("({:.9g}, {:.9g})", x[0], x[1]);
}

}  // namespace bouncecal::dem::scene::particle_file
