#ifndef BOUNCECAL_DEM_ENGINE_ENERGY_BUDGET_H_
#define BOUNCECAL_DEM_ENGINE_ENERGY_BUDGET_H_

#include <cstdint>

#include "bouncecal/dem/scene.h"
#include "engine/engine.h"

namespace bouncecal::dem::scene {

// The most kinetic energy a stably integrated scene can hold: what its particles bring in (launch
// speed and spin, height above the floor, the elastic energy of overlaps in the start) plus what
// van der Waals can release. Contacts, damping and friction only take energy out, so kinetic
// energy well beyond this is energy the integrator made: an unstable step. It catches the packs
// that blow up below the single-contact limit (several contacts stiffen a particle), long before
// a particle is fast enough to cross half its radius in one step.
class EnergyBudget {
 public:
  // The particles already in the engine, and an allowance for van der Waals over
  // `total_particles` (those still to be poured included).
  template <int Dim>
  EnergyBudget(const Scene& scene, const EngineBase<Dim>& engine, std::int64_t total_particles);

  // Adds what the particles from index `first_new` on bring in (a pour batch: placed without
  // overlaps, so their kinetic and potential energy only).
  template <int Dim>
  void AddInserted(const EngineBase<Dim>& engine, std::int32_t first_new);

  // False when the floor does not bound the fall (a lone plane that is not horizontal): then
  // there is no budget to hold the run to.
  bool bounded() const { return bounded_; }
  double joules() const { return joules_; }
  // A resumed pack takes the budget its checkpoint saved: the particles' start energies are
  // not recoverable from a later state.
  void RestoreJoules(double joules) { joules_ = joules; }

 private:
  const Scene& scene_;
  bool bounded_ = true;
  double joules_ = 0;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_ENERGY_BUDGET_H_
