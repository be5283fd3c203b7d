#ifndef BOUNCECAL_DEM_ENGINE_VAN_DER_WAALS_H_
#define BOUNCECAL_DEM_ENGINE_VAN_DER_WAALS_H_

// Van der Waals attraction between spheres, a physics option of the packing engine
// (PhysicsSpec::van_der_waals, paper 004). The engine lists pairs out to vdw_cutoff_gap_m beyond
// contact and pulls every listed pair within it, touching or not; the scene checks use the same
// force law to refuse a material whose contacts cannot hold the pull (contact_limits.cc).

#include <algorithm>

namespace bouncecal::dem::scene {

// Hamaker (1937) sphere-sphere attraction for gaps h << R: F = A R_eff / (6 h^2), i.e.
// A R / (12 h^2) for equal spheres (paper 004 eq. 2). It diverges at contact, so the gap is
// floored at min_gap_m (vdw_min_gap_m: an interatomic distance, Israelachvili ch. 13); an
// overlap (> 0) counts as contact. Magnitude, towards the other particle. Real: double, or float
// in the packing engine's single-precision contacts (EngineSettings::single_precision_contacts).
template <class Real>
inline Real VanDerWaalsForceN(Real overlap_m, Real effective_radius_m, Real hamaker_j,
                              Real min_gap_m) {
  const Real gap = std::max(-overlap_m, min_gap_m);
  return hamaker_j * effective_radius_m / (6 * gap * gap);
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_VAN_DER_WAALS_H_
