#ifndef BOUNCECAL_DEM_LAWS_WALTON_BRAUN_PLASTIC_H_
#define BOUNCECAL_DEM_LAWS_WALTON_BRAUN_PLASTIC_H_

#include <optional>
#include <span>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/law_common.h"

namespace bouncecal::dem {

// Walton & Braun (1986, J. Rheol. 30, 949) hysteretic contact with a plastic offset, the form
// LIGGGHTS (hooke/hysteresis), Yade and MercuryDPM users know (Luding 2008, Granular Matter 10):
//   loading (xi at its maximum so far):  F = k1 xi
//   unloading/reloading below xi_max:    F = max(0, k2 (xi - xi_0)),  xi_0 = xi_max (1 - k1/k2)
// with k2 >= k1. Energy is lost only in the first loading; e = sqrt(k1/k2) for every impact
// speed. Unlike Luding's variant, k2 is constant (no growth with xi_max), so this is the original
// 1986 form. The contact (and the history) lasts while the geometric overlap is positive; between
// xi_0 and 0 the force is zero, which the closed-form duration includes.
class WaltonBraunPlastic {
 public:
  static constexpr ContactLawKind kKind = ContactLawKind::kWaltonBraunPlastic;
  static constexpr bool kNeedsHistory = true;

  struct Params {
    double stiffness_n_per_m = 1e7;            // k1, loading, (0, inf)
    double unloading_stiffness_n_per_m = 3e7;  // k2 >= k1; 3 k1 gives e = 0.577 like gamma_n 0.5
  };

  explicit WaltonBraunPlastic(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  double NormalForce(const NormalContact& contact, NormalHistory& history) const {
    if (contact.overlap_m <= 0) return 0;
    if (contact.overlap_m >= history.max_overlap_m) {
      history.max_overlap_m = contact.overlap_m;
      return params_.stiffness_n_per_m * contact.overlap_m;
    }
    const double offset = history.max_overlap_m *
                          (1 - params_.stiffness_n_per_m / params_.unloading_stiffness_n_per_m);
    const double force = params_.unloading_stiffness_n_per_m * (contact.overlap_m - offset);
    return force > 0 ? force : 0;
  }

  // Gravity-free: e = sqrt(k1/k2); the duration includes the force-free stretch from xi_0 to 0.
  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;
  ExactImpact SolveImpactExactly(double mass_kg, double gravity_mps2,
                                 double impact_speed_mps) const;

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_WALTON_BRAUN_PLASTIC_H_
