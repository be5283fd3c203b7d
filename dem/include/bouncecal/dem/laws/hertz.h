#ifndef BOUNCECAL_DEM_LAWS_HERTZ_H_
#define BOUNCECAL_DEM_LAWS_HERTZ_H_

#include <cmath>
#include <optional>
#include <span>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::dem {

// Hertz elastic contact (Hertz 1882; Johnson, Contact Mechanics, 1985, eq. 4.23):
//   F = (4/3) E* sqrt(R_eff) xi^(3/2),  1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.
// No dissipation: e = 1. Contact duration (Johnson 1985, eq. 11.24):
//   t_c = 2 I xi_max / v,  xi_max = (15 m v^2 / (16 E* sqrt(R)))^(2/5),
//   I = integral_0^1 (1 - x^(5/2))^(-1/2) dx = Gamma(7/5) Gamma(1/2) / Gamma(9/10) = 1.4716,
// so t_c grows as v^(-1/5) for slower impacts.
class Hertz {
 public:
  static constexpr std::string_view kName = "hertz";
  static constexpr bool kNeedsHistory = false;

  struct Params {
    double effective_modulus_pa = 1.1e11;  // E*, steel on steel (E = 200 GPa, nu = 0.3)
  };

  explicit Hertz(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  double NormalForce(const NormalContact& contact, NormalHistory& /*history*/) const {
    if (contact.overlap_m <= 0) return 0;
    return Stiffness(contact.effective_radius_m) * contact.overlap_m * std::sqrt(contact.overlap_m);
  }
  // (4/3) E* sqrt(R): F = Stiffness(R) xi^(3/2).
  double Stiffness(double effective_radius_m) const {
    return 4.0 / 3.0 * params_.effective_modulus_pa * std::sqrt(effective_radius_m);
  }

  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  // 0.6 x (omega dt < 2) with the tangent stiffness 1.5 K sqrt(xi_max) at the deepest overlap an
  // impact at this speed reaches under gravity (energy bound, so every slower impact is
  // covered); the 0.6 margin covers the overshoot of a stiffening contact (see hertz.cc).
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;

  // Gravity-free maximum overlap of an impact at impact_speed_mps.
  double MaxOverlapM(double effective_mass_kg, double effective_radius_m,
                     double impact_speed_mps) const;

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_HERTZ_H_
