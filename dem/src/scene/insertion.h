#ifndef BOUNCECAL_DEM_SCENE_INSERTION_H_
#define BOUNCECAL_DEM_SCENE_INSERTION_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem::scene {

struct NewParticle {
  Vec3 position_m{0, 0, 0};
  double radius_m = 0;
  std::int32_t species = 0;
};

// A small, portable random source (SplitMix64, Steele et al. 2014): the same seed gives the same
// scene on every compiler and standard library, which std::uniform_real_distribution does not
// promise.
class SceneRandom {
 public:
  explicit SceneRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next();
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

 private:
  std::uint64_t state_;
};

// The diameters and species of all `count` particles of a scene, in insertion order: species
// counts follow the volume fractions exactly (largest remainder; with one diameter distribution
// for all species the number fraction equals the volume fraction), shuffled with the seed.
std::vector<NewParticle> DrawParticles(const Scene& scene, SceneRandom& random);

// A pour batch gives up on a particle after this many overlapping tries in a row.
inline constexpr std::int64_t kPourMissesPerParticle = 20000;

// Places as many of `pending` (front first) as fit in the region without overlapping each other
// or the `existing` particles, trying at most max_attempts random centres. Returns the placed
// ones; the caller keeps the rest for a later batch.
std::vector<NewParticle> PlaceInRegion(const Scene& scene, const std::vector<NewParticle>& pending,
                                       const std::vector<NewParticle>& existing,
                                       SceneRandom& random);

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

#endif  // BOUNCECAL_DEM_SCENE_INSERTION_H_
