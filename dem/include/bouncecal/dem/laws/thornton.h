#ifndef BOUNCECAL_DEM_LAWS_THORNTON_H_
#define BOUNCECAL_DEM_LAWS_THORNTON_H_

#include <cmath>
#include <numbers>
#include <optional>
#include <span>
#include <string_view>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/law_common.h"

namespace bouncecal::dem {

// Elastic-perfectly plastic normal contact of Thornton (1997, J. Appl. Mech. 64, 383-386):
//   loading, xi <= xi_y:  F = K xi^(3/2),  K = (4/3) E* sqrt(R_eff)                     (Hertz)
//   loading, xi >  xi_y:  F = F_y + pi p_y R_eff (xi - xi_y)
//   unloading/reloading:  F = (4/3) E* sqrt(R_p) (xi - xi_p)^(3/2), zero below xi_p
// The contact pressure is capped at the yield pressure p_y: yield starts where the Hertz peak
// pressure 2 E* a / (pi R) reaches p_y, a_y = pi R p_y / (2 E*), xi_y = a_y^2 / R, F_y = K
// xi_y^(3/2); beyond it the area a^2 = R xi grows at the pressure p_y. Unloading is Hertzian from
// the maximum overlap xi_m with the flattened radius R_p = 4 E* a_m^3 / (3 F_m) (a_m^2 = R xi_m,
// F_m the force there) and the dent xi_p = xi_m - a_m^2 / R_p. Per-contact memory: the maximum
// overlap. Energy balance (gravity-free) gives the yield speed v_y^2 = (4/5) F_y xi_y / m_eff (a
// sphere of density rho on a plane: v_y = (pi^2 / sqrt(40)) sqrt(p_y^5 / (E*^4 rho)),
// Thornton's 1.56) and, above it, with u = v_y / v (Thornton's closed form, derived step by step in
// docs/physics.md):
//   e = sqrt(6 sqrt(3) / 5) sqrt(1 - u^2 / 6) [u / (u + 2 sqrt(6/5 - u^2/5))]^(1/4),
// e = 1 at and below v_y, falling as v^(-1/4) at high speed (a steel ball on a copper plate).
class Thornton {
 public:
  static constexpr std::string_view kName = "thornton";
  static constexpr bool kNeedsHistory = true;

  struct Params {
    double effective_modulus_pa = 1.1e11;  // E*, steel on steel
    double yield_pressure_pa = 1.4e9;      // p_y, (0, 2 E*/pi); e = 0.568 for the paper's drop
  };

  explicit Thornton(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  double NormalForce(const NormalContact& contact, NormalHistory& history) const {
    if (contact.overlap_m <= 0) return 0;
    if (contact.overlap_m >= history.max_overlap_m) {
      history.max_overlap_m = contact.overlap_m;
      return LoadingForce(contact.overlap_m, contact.effective_radius_m);
    }
    const Unloading branch = UnloadingFrom(history.max_overlap_m, contact.effective_radius_m);
    const double elastic = contact.overlap_m - branch.dent_m;
    return elastic > 0 ? branch.stiffness * elastic * std::sqrt(elastic) : 0;
  }

  // (4/3) E* sqrt(R): the Hertz branch is F = HertzStiffness(R) xi^(3/2).
  double HertzStiffness(double effective_radius_m) const {
    return 4.0 / 3.0 * params_.effective_modulus_pa * std::sqrt(effective_radius_m);
  }
  // xi_y = R (pi p_y / (2 E*))^2.
  double YieldOverlapM(double effective_radius_m) const {
    const double strain = std::numbers::pi * params_.yield_pressure_pa /
                          (2 * params_.effective_modulus_pa);  // a_y / R
    return effective_radius_m * strain * strain;
  }
  double LoadingForce(double overlap_m, double effective_radius_m) const {
    const double yield = YieldOverlapM(effective_radius_m);
    const double stiffness = HertzStiffness(effective_radius_m);
    if (overlap_m <= yield) return stiffness * overlap_m * std::sqrt(overlap_m);
    return stiffness * yield * std::sqrt(yield) +
           std::numbers::pi * params_.yield_pressure_pa * effective_radius_m * (overlap_m - yield);
  }

  // The Hertzian unloading branch after a loading to max_overlap_m: F = stiffness (xi - dent)^1.5.
  struct Unloading {
    double stiffness = 0;  // (4/3) E* sqrt(R_p)
    double dent_m = 0;     // xi_p, the overlap at which the force returns to zero
  };
  Unloading UnloadingFrom(double max_overlap_m, double effective_radius_m) const {
    if (max_overlap_m <= YieldOverlapM(effective_radius_m)) {
      return {HertzStiffness(effective_radius_m), 0};
    }
    // R_p = 4 E* a^3 / (3 F), a^2 = R xi_m; the elastic recovery a^2 / R_p = 3 F / (4 E* a).
    const double force = LoadingForce(max_overlap_m, effective_radius_m);
    const double contact_radius = std::sqrt(effective_radius_m * max_overlap_m);
    const double flattened_radius = 4 * params_.effective_modulus_pa * contact_radius *
                                    contact_radius * contact_radius / (3 * force);
    return {4.0 / 3.0 * params_.effective_modulus_pa * std::sqrt(flattened_radius),
            max_overlap_m - contact_radius * contact_radius / flattened_radius};
  }

  // Gravity-free impact speed below which the contact stays elastic (e = 1).
  double YieldSpeedMps(double effective_mass_kg, double effective_radius_m) const;
  // Thornton's closed form above; 1 at or below the yield speed.
  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  // Gravity-free: the Hertz loading to xi_y, the harmonic plastic loading to xi_m, the Hertz
  // unloading on R_p to the dent and the force-free stretch from the dent to overlap 0.
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  // 0.6 x (omega dt < 2) with the largest tangent stiffness, 2 E* sqrt(R xi_m), at the deepest
  // overlap an impact at this speed reaches under gravity (as for hertz, whose margin it shares).
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;
  // Neither engine has a plastic Hertz contact; see thornton.cc.
  EngineForm ExportForm() const;

  // Work done on the contact loading it from 0 to overlap_m.
  double LoadingWorkJ(double overlap_m, double effective_radius_m) const;

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_THORNTON_H_
