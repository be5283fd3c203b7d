#ifndef BOUNCECAL_DEM_PACK_PROJECTION_H_
#define BOUNCECAL_DEM_PACK_PROJECTION_H_

// How long a packing run will take: a prior from the engine's measured speed on the reference
// host before the first step (docs/packing.md, "Scale"), then the run's own measured speed.

#include <cstdint>
#include <string>

#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::dem {

// Particle-steps per second of wall time the 3D engine reached on the reference host for a
// settled pack of `particles` spheres (the costly regime; a pour's falling phase runs faster) on
// `threads` threads: the table in docs/packing.md, interpolated in log-log between its rows.
double ReferenceParticleStepsPerS(std::int64_t particles, int threads);

// Prior wall time of `steps` steps with `particles` spheres at the reference speed.
double ProjectWallTimeS(std::int64_t particles, std::int64_t steps, int threads);

// The whole scene run as `options` set it up (duration override, threads): its particle count
// and its step count at the reference speed.
double ProjectWallTimeS(const Scene& scene, const PackOptions& options);

// "about 2 min 40 s for 2000 particles x 300000 steps on 2 threads (reference host speed ...)"
std::string DescribeProjection(const Scene& scene, const PackOptions& options);

// The remaining wall time of a run from its own progress: particle-steps per wall second measured
// over the recent stretch (the cost per particle-step grows as a pour settles), applied to the
// remaining steps at the final particle count. Before any stretch was measured, the prior.
class WallTimeProjection {
 public:
  // `first_step` and `first_wall_s`: where the stepping starts (a resumed run's checkpoint step;
  // the wall clock after the set-up, which is not stepping speed).
  WallTimeProjection(std::int64_t final_particles, std::int64_t total_steps, int threads,
                     std::int64_t first_step = 0, double first_wall_s = 0);

  // After `steps_done` steps of the run and `wall_s` seconds, with `particles` in the scene.
  // Returns the projected remaining wall time.
  double Update(std::int64_t steps_done, std::int64_t particles, double wall_s);

  double prior_s() const { return prior_s_; }

 private:
  std::int64_t final_particles_;
  std::int64_t total_steps_;
  double prior_s_;
  double prior_rate_;
  std::int64_t last_steps_ = 0;
  double last_wall_s_ = 0;
  double rate_ = 0;  // smoothed particle-steps per wall second; 0 until measured
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_PACK_PROJECTION_H_
