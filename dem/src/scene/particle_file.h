#ifndef BOUNCECAL_DEM_SCENE_PARTICLE_FILE_H_
#define BOUNCECAL_DEM_SCENE_PARTICLE_FILE_H_

// Start-positions files (insertion type "file"): read one, in either format, and check it on its
// own and against the scene. The format parsers are particle_file_csv.cc and
// particle_file_lammps.cc, the overlap check overlap_checks.cc.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "bouncecal/dem/scene.h"
#include "scene/insertion.h"

namespace bouncecal::dem::scene {

// a <= b up to rounding (1e-9 of the larger magnitude), so that a region drawn equal to its
// container, or a position written out and read back, is not refused.
inline bool AtMostUpToRounding(double a, double b) {
  return a <= b + 1e-9 * std::max(std::abs(a), std::abs(b));
}

// Reads positions (and diameters) from a CSV file with a header naming the columns
// x_m,y_m[,z_m],diameter_m[,species] (a UTF-8 byte order mark before it is skipped) or from a
// LAMMPS data file (atom_style sphere: id type diameter density x y z). Throws InputError naming
// the file and line for a malformed row, an empty file, a LAMMPS 'N atoms' header that differs
// from the rows of the Atoms section, a repeated atom id, a non-zero z in 2D, and two particles
// closer than half the sum of their radii (coincident or heavily overlapping).
std::vector<NewParticle> ReadParticleFile(const std::filesystem::path& path, int dimension);

// ReadParticleFile(scene.insertion.file, scene.dimension), checked against the scene as well:
// every species exists, every particle lies inside the container (overlapping a wall by at most
// half its radius, as in a settled pack; any height above an open top), and the file holds
// particles.count particles. Throws InputError naming the file and line, or the scene key.
std::vector<NewParticle> ReadParticleFile(const Scene& scene);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_PARTICLE_FILE_H_
