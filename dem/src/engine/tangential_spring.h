#ifndef BOUNCECAL_DEM_ENGINE_TANGENTIAL_SPRING_H_
#define BOUNCECAL_DEM_ENGINE_TANGENTIAL_SPRING_H_

// The tangential contact force of the packing engine (PhysicsSpec::tangential): a Cundall &
// Strack (1979) spring on the accumulated tangential displacement, capped by Coulomb friction
// (paper 000 eq. 5-6), and the twist n x F_t its force exerts (PhysicsSpec::rotation). Each
// contact keeps its spring from step to step (the engine's pair and wall spring arrays). The
// functions work on one contact's components in local arrays, so that the contact stages
// (contact_stages.h) can call them inside loops the compiler vectorises across contacts: no
// branches, selects only.

#include <cmath>

namespace bouncecal::dem::scene {

// Sum of the squares, started from the first square rather than from 0: 0 + x x is x x for
// every x (a square is never -0), so the value is that of the plain sum, and the compiler,
// which must keep the addition of a 0 it cannot prove redundant, saves one per sum.
template <int Dim, class Real>
[[gnu::always_inline]] inline Real SumOfSquares(const Real (&v)[Dim]) {
  Real sum = v[0] * v[0];
  for (int c = 1; c < Dim; ++c) sum += v[c] * v[c];
  return sum;
}

// Turns a contact's spring into the tangent plane of the unit normal n, keeping its length, so
// that a rolling contact does not grow a normal component (LAMMPS gran/hooke/history projects
// without the rescale; pair granular rescales like this). The projection is done in place; the
// factor that restores the length is returned, to be applied by CoulombSpringForce. With no
// spring, or none left after the projection, the factor is 1.
template <int Dim, class Real>
[[gnu::always_inline]] inline Real ProjectSpring(Real (&spring)[Dim], const Real (&n)[Dim]) {
  const Real old2 = SumOfSquares<Dim>(spring);
  Real along = 0;
  for (int c = 0; c < Dim; ++c) along += spring[c] * n[c];
  Real projected[Dim];
  for (int c = 0; c < Dim; ++c) projected[c] = spring[c] - along * n[c];
  const Real new2 = SumOfSquares<Dim>(projected);
  const bool had_spring = old2 > 0;
  for (int c = 0; c < Dim; ++c) spring[c] = had_spring ? projected[c] : spring[c];
  const bool rescale = had_spring & (new2 > 0);
  return std::sqrt((rescale ? old2 : Real{1}) / (rescale ? new2 : Real{1}));
}

// The spring's constants for a run, in the precision of the contact arithmetic (double, or
// float for EngineSettings::single_precision_contacts).
template <class Real>
struct BasicSpringConstants {
  Real time_step_s;
  Real stiffness_n_per_m;        // k_t
  Real shear_per_force_m_per_n;  // 1 / -k_t: the spring of a sliding contact from its force
};
using SpringConstants = BasicSpringConstants<double>;

// One step of the spring: its projected length restored (length_factor from ProjectSpring), the
// step's tangential displacement dt v_t added, and the force -k_t s. When that force exceeds
// friction |F_n| the contact slides: the force is scaled back to the Coulomb cap and the spring
// reset to match it, so |F_t| never exceeds mu |F_n|. Writes the new spring back and returns the
// tangential force in `tangential`.
template <int Dim, class Real>
[[gnu::always_inline]] inline void CoulombSpringForce(Real (&spring)[Dim], Real length_factor,
                                                      const Real (&tangential_velocity)[Dim],
                                                      Real normal_force, Real friction,
                                                      const BasicSpringConstants<Real>& constants,
                                                      Real (&tangential)[Dim]) {
  const Real dt = constants.time_step_s;
  const Real ks = constants.stiffness_n_per_m;
  Real shear[Dim];
  for (int c = 0; c < Dim; ++c) {
    shear[c] = spring[c] * length_factor;
    shear[c] += dt * tangential_velocity[c];
    tangential[c] = shear[c] * -ks;
  }
  const Real cap = friction * std::abs(normal_force);
  const Real f2 = SumOfSquares<Dim>(tangential);
  const bool slides = f2 > cap * cap;
  const Real scale = cap / std::sqrt(f2);
  for (int c = 0; c < Dim; ++c) {
    const Real capped = tangential[c] * scale;
    tangential[c] = slides ? capped : tangential[c];
    spring[c] = slides ? capped * constants.shear_per_force_m_per_n : shear[c];
  }
}

// n x F_t, the twist of the tangential force: the torque on either body of a contact is
// -r (n x F_t) with r its radius (for the second body of a pair both the normal and the force
// change sign). In 2D the twist is its z component.
template <int Dim, class Real>
[[gnu::always_inline]] inline void SpringTwist(const Real (&n)[Dim], const Real (&tangential)[Dim],
                                               Real (&twist)[Dim == 3 ? 3 : 1]) {
  if constexpr (Dim == 3) {
    twist[0] = n[1] * tangential[2] - n[2] * tangential[1];
    twist[1] = n[2] * tangential[0] - n[0] * tangential[2];
    twist[2] = n[0] * tangential[1] - n[1] * tangential[0];
  } else {
    twist[0] = n[0] * tangential[1] - n[1] * tangential[0];
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_TANGENTIAL_SPRING_H_
