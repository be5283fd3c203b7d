#ifndef BOUNCECAL_DEM_SCENE_INSERTION_H_
#define BOUNCECAL_DEM_SCENE_INSERTION_H_

// Particles for a scene: their sizes and species drawn at random, and centres drawn at random in
// the insertion region without overlap (insertion types "random" and "pour"). Start-positions
// files (type "file") are read by particle_file.h.

#include <cstdint>
#include <vector>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem::scene {

struct NewParticle {
  Vec3 position_m{0, 0, 0};
  double radius_m = 0;
  std::int32_t species = 0;
};

// A small, portable random source (one SplitMix64 sequence, core/random_stream.h): the same seed
// gives the same scene on every compiler and standard library, which std::uniform_real_distribution
// does not promise.
class SceneRandom {
 public:
  explicit SceneRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next();
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // SplitMix64's whole state is one word, so SceneRandom(state()) continues the same stream
  // (a pack checkpoint saves it).
  std::uint64_t state() const { return state_; }

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

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_INSERTION_H_
