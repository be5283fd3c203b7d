#ifndef BOUNCECAL_DEM_ENGINE_INTEGRATOR_H_
#define BOUNCECAL_DEM_ENGINE_INTEGRATOR_H_

// The packing engine's time integration: velocity Verlet (Verlet 1967; Allen & Tildesley ch. 3)
// on one particle record. Engine::Advance fuses the closing half kick of one step into the
// opening half kick and drift of the next, so a step costs two passes over the particles: the
// pair pass, then one pass that sums each particle's load and calls VerletKickDrift (or, after
// the last step of a call, VerletHalfKick). Kept apart from the force loop so the integrator can
// be read, and changed, without the contact code around it.

#include "engine/particle_records.h"
#include "scene/vec.h"

namespace bouncecal::dem::scene {

// The force and torque on a particle.
template <int Dim>
struct ParticleLoad {
  Vec<Dim> force;
  Spin<Dim> torque;
};

// v(t + dt/2) = v + kick a; x += dt v (and the spin kicked likewise when kRotation). Returns
// the squared distance moved since the last neighbour-list build (the record's origin).
template <int Dim, bool kRotation>
[[gnu::always_inline]] inline double VerletKickDrift(ParticleRecord<Dim>& record, double kick,
                                                     double dt, const ParticleLoad<Dim>& load) {
  // Component by component, each new value kept in a register: whole-vector assignments made
  // GCC re-read components just stored one by one as one wider load (or copy them through the
  // stack), which cannot be store-forwarded and stalled the loop. Same operations, same results.
  const double velocity_kick = kick * record.inverse_mass;
  auto& velocity = record.velocity_mass.v;
  auto& position = record.position_radius.v;
  const auto& origin = record.origin;
  double move2 = 0;
  for (int d = 0; d < Dim; ++d) {
    const double v = velocity[d] + velocity_kick * load.force[d];
    velocity[d] = v;
    const double x = position[d] + dt * v;
    position[d] = x;
    const double moved = x - origin[d];
    move2 += moved * moved;
  }
  if constexpr (kRotation) {
    const double spin_kick = kick * record.spin_inertia.inverse_inertia;
    if constexpr (Dim == 3) {
      for (int d = 0; d < 3; ++d) record.spin_inertia.w[d] += spin_kick * load.torque[d];
    } else {
      record.spin_inertia.w += spin_kick * load.torque;
    }
  }
  return move2;
}

// v(t + dt) = v(t + dt/2) + dt/2 a(t + dt): closes the step without drifting.
template <int Dim, bool kRotation>
inline void VerletHalfKick(ParticleRecord<Dim>& record, double half_dt,
                           const ParticleLoad<Dim>& load) {
  record.velocity_mass.v += (half_dt * record.inverse_mass) * load.force;
  if constexpr (kRotation)
    record.spin_inertia.w += (half_dt * record.spin_inertia.inverse_inertia) * load.torque;
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_INTEGRATOR_H_
