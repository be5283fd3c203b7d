#ifndef BOUNCECAL_DEM_LAWS_LINEAR_DASHPOT_H_
#define BOUNCECAL_DEM_LAWS_LINEAR_DASHPOT_H_

#include <cmath>
#include <optional>
#include <span>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/law_common.h"

namespace bouncecal::dem {

// Linear spring-dashpot (Cundall & Strack 1979, Geotechnique 29; Tsuji et al. 1992 form of the
// coefficient):  F = k xi + c d xi/dt,  c = 2 zeta sqrt(m_eff k),  zeta = damping_ratio in [0, 1].
// Without gravity e = exp(-pi zeta / sqrt(1 - zeta^2)) and t_c = pi / (omega sqrt(1 - zeta^2)),
// omega = sqrt(k / m_eff), independent of the impact speed. The force is NOT clipped at zero: near
// the end of the contact the dashpot pulls (attractive force), as in LAMMPS/LIGGGHTS without
// limit_damping/limitForce; this is what makes the closed forms exact. zeta = 1 (critical) never
// releases the ball.
class LinearDashpot {
 public:
  static constexpr std::string_view kName = "linear-dashpot";
  static constexpr bool kNeedsHistory = false;

  struct Params {
    double stiffness_n_per_m = 1e7;  // k, (0, inf)
    double damping_ratio = 0.1722;   // zeta in [0, 1]; 0.1722 gives e = 0.577 like gamma_n 0.5
  };

  explicit LinearDashpot(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  // At zero overlap the force is the dashpot's c * rate while approaching (the right-hand limit:
  // the dashpot force jumps at touchdown, a known property of this model), else 0.
  double NormalForce(const NormalContact& contact, NormalHistory& /*history*/) const {
    if (contact.overlap_m < 0 || (contact.overlap_m == 0 && contact.overlap_rate_mps <= 0)) {
      return 0;
    }
    const double damping = 2 * params_.damping_ratio *
                           std::sqrt(contact.effective_mass_kg * params_.stiffness_n_per_m);
    return params_.stiffness_n_per_m * contact.overlap_m + damping * contact.overlap_rate_mps;
  }

  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  // omega dt < 2 (sqrt(1 + zeta^2) - zeta): the central-difference limit with viscous damping
  // (O'Sullivan & Bray 2004, Eng. Comput. 21).
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;
  ExactImpact SolveImpactExactly(double mass_kg, double gravity_mps2,
                                 double impact_speed_mps) const;

  // The engines' own spring-dashpot (LAMMPS gran/hooke, LIGGGHTS hooke/stiffness).
  EngineForm ExportForm() const {
    return EngineSpringDashpot{.stiffness_n_per_m = params_.stiffness_n_per_m,
                               .damping_ratio = params_.damping_ratio};
  }
  // The damping ratio that gives restitution e without gravity: -ln e / sqrt(pi^2 + ln^2 e).
  static double DampingRatioForRestitution(double restitution);

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_LINEAR_DASHPOT_H_
