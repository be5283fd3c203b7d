#ifndef BOUNCECAL_DEM_SCENE_PARTICLE_FILE_PARSERS_H_
#define BOUNCECAL_DEM_SCENE_PARTICLE_FILE_PARSERS_H_

// The parsers of the two start-positions formats (a CSV with named columns, a LAMMPS data file)
// and the field helpers they share. Internal to the particle-file reader (particle_file.cc) and
// its checks, which name a particle by the file line it came from.

#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "scene/insertion.h"

namespace bouncecal::dem::scene::particle_file {

// A particle of a start-positions file and the line it came from, for messages.
struct FileParticle {
  NewParticle particle;
  int line = 0;
};

// A CSV file with a header naming the columns x_m,y_m[,z_m],diameter_m[,species] (a UTF-8 byte
// order mark before it is skipped).
std::vector<FileParticle> ReadCsv(std::istream& in, const std::filesystem::path& path,
                                  int dimension);

// A LAMMPS data file, atom_style sphere (id type diameter density x y z), in the order of the
// atom ids.
std::vector<FileParticle> ReadLammpsData(std::istream& in, const std::filesystem::path& path,
                                         int dimension);

// Fields of a line, split at commas (trimmed) or at white space.
std::vector<std::string> SplitFields(const std::string& line, bool commas);
// "path:line", the start of every message about a line.
std::string Where(const std::filesystem::path& path, int line);
// A finite number, the whole field; throws InputError naming the line otherwise.
double ParseNumber(const std::string& text, const std::filesystem::path& path, int line);
// A whole number in [min, max]: species, type, id and atom counts.
std::int64_t ParseWhole(const std::string& text, const std::filesystem::path& path, int line,
                        double min, double max);
// Throws InputError unless z is 0 (a 2D scene's particles lie in the x-y plane).
void RefuseZIn2d(double z, const std::filesystem::path& path, int line);
// The scene's count check (ParticleCountProblem) applied to a start-positions file.
void RefuseCount(const std::filesystem::path& path, double count, int dimension);
// A position for messages, with as many components as the scene has.
std::string Position(const Vec3& x, int dimension);

inline constexpr double kMaxSpecies = 1e6;

}  // namespace bouncecal::dem::scene::particle_file

#endif  // BOUNCECAL_DEM_SCENE_PARTICLE_FILE_PARSERS_H_
