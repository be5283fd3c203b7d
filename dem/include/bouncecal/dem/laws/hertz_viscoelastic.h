#ifndef BOUNCECAL_DEM_LAWS_HERTZ_VISCOELASTIC_H_
#define BOUNCECAL_DEM_LAWS_HERTZ_VISCOELASTIC_H_

#include <cmath>
#include <optional>
#include <span>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::dem {

// Hertz contact with viscoelastic damping after Brilliantov et al. (1996, Phys. Rev. E 53, 5382):
//   F = K (xi^(3/2) + (3/2) A sqrt(xi) d xi/dt),  K = (4/3) E* sqrt(R_eff),
// with A the dissipative time (s) of the material. Restitution falls with impact speed, as the
// measured eta_k of a bouncing ball does (docs/physics.md section 1). Chosen over Tsuji's
// xi^(1/4) form because Tsuji's damping gives a speed-independent restitution, which the linear
// laws already cover. The force is clipped at zero (no attraction: the surfaces separate when it
// would pull, Schwager & Poeschel 2008, Phys. Rev. E 78, 051304).
// Closed-form restitution (Ramirez et al. 1999, Phys. Rev. E 60, 4465), to second order:
//   e = 1 - C1 A a^(2/5) v^(1/5) + C2 A^2 a^(4/5) v^(2/5),  a = (3/2)^(5/2) K / m_eff
//   (their a = (3/2)^(3/2) Y sqrt(R) / (m (1 - nu^2)) with K = (2/3) Y sqrt(R) / (1 - nu^2)),
//   C1 = 1.15344, C2 = 0.79826; valid while C1 A a^(2/5) v^(1/5) << 1.
class HertzViscoelastic {
 public:
  static constexpr std::string_view kName = "hertz-viscoelastic";
  static constexpr bool kNeedsHistory = false;

  struct Params {
    double effective_modulus_pa = 1.1e11;  // E*, steel on steel
    double dissipative_time_s = 2e-6;      // A, [0, 1e-2]
  };

  explicit HertzViscoelastic(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  double NormalForce(const NormalContact& contact, NormalHistory& /*history*/) const {
    if (contact.overlap_m <= 0) return 0;
    const double root = std::sqrt(contact.overlap_m);
    const double force = Stiffness(contact.effective_radius_m) *
                         (contact.overlap_m * root +
                          1.5 * params_.dissipative_time_s * root * contact.overlap_rate_mps);
    return force > 0 ? force : 0;
  }
  double Stiffness(double effective_radius_m) const {
    return 4.0 / 3.0 * params_.effective_modulus_pa * std::sqrt(effective_radius_m);
  }

  // The second-order expansion above (clamped to [0, 1]); no closed-form duration.
  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_HERTZ_VISCOELASTIC_H_
