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
// with k2 >= k1. Energy is lost only in the first loading; e = sqrt(k1/k2). With
// plastic_flow_overlap_m = 0 (default) k2 is constant: the original 1986 form, e independent of
// the impact speed. With xi_f = plastic_flow_overlap_m > 0, Luding's variant: the unloading
// stiffness grows with the maximum overlap, k2(xi_max) = k1 + (k2 - k1) min(1, xi_max / xi_f),
// so slow impacts are nearly elastic and e falls with impact speed until xi_max reaches xi_f.
// The contact (and the history) lasts while the geometric overlap is positive; between xi_0 and
// 0 the force is zero, which the closed-form duration includes.
class WaltonBraunPlastic {
 public:
  static constexpr std::string_view kName = "walton-braun-plastic";
  static constexpr bool kNeedsHistory = true;

  struct Params {
    double stiffness_n_per_m = 1e7;            // k1, loading, (0, inf)
    double unloading_stiffness_n_per_m = 3e7;  // k2 >= k1; 3 k1 gives e = 0.577 like gamma_n 0.5
    double plastic_flow_overlap_m = 0;         // xi_f, [0, 1]; 0: constant k2 (1986 form)
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
    const double unloading = UnloadingStiffness(history.max_overlap_m);
    const double offset = history.max_overlap_m * (1 - params_.stiffness_n_per_m / unloading);
    const double force = unloading * (contact.overlap_m - offset);
    return force > 0 ? force : 0;
  }

  // k2 after a loading to max_overlap_m (constant unless plastic_flow_overlap_m > 0).
  double UnloadingStiffness(double max_overlap_m) const {
    if (params_.plastic_flow_overlap_m <= 0) return params_.unloading_stiffness_n_per_m;
    const double k1 = params_.stiffness_n_per_m;
    const double reach = max_overlap_m / params_.plastic_flow_overlap_m;
    return k1 + (params_.unloading_stiffness_n_per_m - k1) * (reach < 1 ? reach : 1);
  }

  // Gravity-free: e = sqrt(k1/k2(xi_max)), xi_max = v sqrt(m/k1); the duration includes the
  // force-free stretch from xi_0 to 0.
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
