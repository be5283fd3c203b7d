#ifndef BOUNCECAL_DEM_ENGINE_CONTACT_LIMITS_H_
#define BOUNCECAL_DEM_ENGINE_CONTACT_LIMITS_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem::scene {

// The particles a scene holds (or will hold), as far as its stiffest contact is concerned.
struct BodyExtremes {
  double lightest_mass_kg = 0;
  double lightest_radius_m = 0;
  double largest_radius_m = 0;
  double largest_mass_kg = 0;  // of the particle with the largest radius
  double highest_top_m = 0;    // highest particle top (or pour region top) above the floor
};

struct TimeStepLimit {
  double limit_s = 0;
  std::string stiffest;  // which contact sets the limit, for the message
};

struct TimeStepLimits {
  // The normal contacts: beyond this every impact gains energy and the run blows up.
  TimeStepLimit normal;
  // The Cundall-Strack spring of a sticking contact (with the sphere's rolling inertia): beyond
  // this it oscillates with growing amplitude until it slides, where the Coulomb cap bounds it.
  // Chatter rather than a blow-up; infinite without tangential physics.
  TimeStepLimit tangential;
};

// The largest step velocity Verlet can take on one contact of this scene: omega dt < 2 with
// omega of the stiffest single contact (normal law at the deepest overlap an impact from the
// highest particle reaches; the tangential spring). A pack loads a particle through several
// contacts at once, so a stable run usually needs a step some way below this. The van der Waals
// attraction is left out: it is flat (floored at vdw_min_gap_m) wherever a contact rests, so it
// shifts the equilibrium (see VanDerWaalsOverlapProblem) but adds no stiffness there.
TimeStepLimits SceneTimeStepLimits(const Scene& scene, const BodyExtremes& bodies);

// SceneTimeStepLimits, applied to the scene's time step: throws ConfigError (naming the scene
// file, the limit and the contact that sets it) beyond the normal limit unless allow_unstable;
// appends a warning beyond kSafeFractionOfLimit of it (several contacts on one particle make a
// stiffer oscillator than one: frictionless pours were seen stable at 0.75 of the limit and
// boiling at 0.8) and one beyond kSafeFractionOfLimit of the tangential limit (beyond it sticking
// contacts chatter; from about 0.65 of it they slip: paper 000's pour and paper 004's box settle
// 0.004-0.03 denser than at a finer step, while up to 0.4 of it they do not move beyond the seed
// spread, docs/packing.md). A scene with a time_step_reason gets those two as notes ending with its
// reason instead (beyond the tangential limit itself it is still warned).
inline constexpr double kSafeFractionOfLimit = 0.5;
TimeStepLimits CheckTimeStep(const Scene& scene, const BodyExtremes& bodies, bool allow_unstable,
                             std::vector<std::string>& warnings, std::vector<std::string>& notes);

// Why, with van der Waals on, the attraction at vdw_min_gap_m would pull two touching particles
// deeper into each other than the contact law holds them apart: an equilibrium overlap beyond
// kMaxVanDerWaalsOverlap of the effective radius, where overlapping spheres are no longer a
// model of touching ones and the run collapses. nullopt when it is fine or vdW is off.
inline constexpr double kMaxVanDerWaalsOverlap = 0.1;
std::optional<std::string> VanDerWaalsOverlapProblem(const Scene& scene,
                                                     const BodyExtremes& bodies);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_CONTACT_LIMITS_H_
