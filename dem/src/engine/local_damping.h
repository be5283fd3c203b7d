#ifndef BOUNCECAL_DEM_ENGINE_LOCAL_DAMPING_H_
#define BOUNCECAL_DEM_ENGINE_LOCAL_DAMPING_H_

// Cundall (1987) local non-viscous damping, as paper 004 (eq. 12) uses it to settle its disk
// packings: each component of a particle's unbalanced force (and torque) is reduced by
// alpha |F| against the velocity (spin). It removes kinetic energy without a velocity scale and
// leaves a state at rest unchanged. A physics option of the packing engine (PhysicsSpec::
// local_damping), applied to the summed load of each particle just before the integrator.

#include <cmath>

#include "scene/vec.h"

namespace bouncecal::dem::scene {

// force and torque (when kRotation) damped in place, alpha in [0, 1).
template <int Dim, bool kRotation>
[[gnu::always_inline]] inline void ApplyLocalDamping(double alpha, const Vec<Dim>& velocity_mps,
                                                     const Spin<Dim>& spin_radps, Vec<Dim>& force_n,
                                                     Spin<Dim>& torque_nm) {
  for (int d = 0; d < Dim; ++d) {
    const double v = velocity_mps[d];
    if (v != 0) force_n[d] -= alpha * std::abs(force_n[d]) * (v > 0 ? 1.0 : -1.0);
  }
  if constexpr (kRotation) {
    if constexpr (Dim == 3) {
      for (int d = 0; d < 3; ++d) {
        const double w = spin_radps[d];
        if (w != 0) torque_nm[d] -= alpha * std::abs(torque_nm[d]) * (w > 0 ? 1.0 : -1.0);
      }
    } else {
      const double w = spin_radps;
      if (w != 0) torque_nm -= alpha * std::abs(torque_nm) * (w > 0 ? 1.0 : -1.0);
    }
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_LOCAL_DAMPING_H_
