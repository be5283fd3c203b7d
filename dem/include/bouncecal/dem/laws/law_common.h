#ifndef BOUNCECAL_DEM_LAWS_LAW_COMMON_H_
#define BOUNCECAL_DEM_LAWS_LAW_COMMON_H_

#include <string_view>
#include <variant>

namespace bouncecal::dem {

// One sphere-on-plane impact solved in closed form with gravity acting during the contact (the
// exact event-driven path of the single-ball drop). Only the piecewise-linear laws provide it.
struct ExactImpact {
  // False when the ball never leaves the plane again (it comes to rest in contact, or the law
  // returns no energy at all): the remaining fields then describe the contact up to maximum
  // compression and speed_out_mps is 0.
  bool released = false;
  double duration_s = 0;     // onset (overlap 0, approaching) to release (overlap 0, leaving)
  double max_overlap_m = 0;  // deepest compression
  double speed_out_mps = 0;  // speed at release, overlap 0
};

// How the linear spring-dashpot that LAMMPS and LIGGGHTS both offer stands in for a law, as the
// law states it through an ExportForm() member (export/src reads it). A law without one
// gets EngineMatchAtSpeed.
// The law is the engines' spring-dashpot, damping coefficient 2 zeta sqrt(m_eff k): exact.
struct EngineSpringDashpot {
  double stiffness_n_per_m = 0;
  double damping_ratio = 0;
};
// Linear hysteresis (loading (1+gamma) k, unloading (1-gamma) k): a spring-dashpot with the same
// e and t_c at every impact speed, since both laws are linear.
struct EngineLinearHysteresis {
  double stiffness_n_per_m = 0;
  double gamma_n = 0;
};
// A spring-dashpot with the law's closed-form e and t_c at a reference impact speed; the deck
// says how much they change with speed.
struct EngineMatchAtSpeed {};
// No engine has the law and a stand-in would mislead: why, for a one-line refusal.
struct NoEngineForm {
  std::string_view reason;
};
using EngineForm =
    std::variant<EngineSpringDashpot, EngineLinearHysteresis, EngineMatchAtSpeed, NoEngineForm>;

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_LAW_COMMON_H_
