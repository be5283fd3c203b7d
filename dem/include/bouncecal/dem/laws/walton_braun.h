#ifndef BOUNCECAL_DEM_LAWS_WALTON_BRAUN_H_
#define BOUNCECAL_DEM_LAWS_WALTON_BRAUN_H_

#include <optional>
#include <span>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/law_common.h"

namespace bouncecal::dem {

// Linear elastic contact with the hysteretic damping used by the paper (acoustic calibration,
// 2009; docs/physics.md section 2), in the spirit of Walton & Braun (1986, J. Rheol. 30):
//   F = k xi + F_d,  F_d = -gamma_n |k xi| sgn(d xi/dt)  (on the body, repulsive > 0)
// so the body is pushed with (1 + gamma_n) k xi while loading and (1 - gamma_n) k xi while
// unloading. Without gravity each impact keeps e = sqrt((1 - gamma)/(1 + gamma)) of the speed,
// eta = 1 - e^2 = 2 gamma / (1 + gamma), independent of the impact speed. gamma_n = 1 returns no
// energy: the ball sticks. The force jumps at the turning point (sgn 0 = 0 gives k xi there),
// which is what limits the order of stepped integrators on this law.
class WaltonBraun {
 public:
  static constexpr std::string_view kName = "walton-braun";
  static constexpr bool kNeedsHistory = false;

  struct Params {
    double stiffness_n_per_m = 1e7;  // k_n, (0, inf)
    double gamma_n = 0.5;            // [0, 1]
  };

  explicit WaltonBraun(const Params& params);
  static Params FromConfig(const ContactLawConfig& config);
  static std::span<const ParameterSpec> Specs();
  const Params& params() const { return params_; }

  double NormalForce(const NormalContact& contact, NormalHistory& /*history*/) const {
    const double elastic = params_.stiffness_n_per_m * contact.overlap_m;
    // Selects, not jumps: in a dense pack the sign of the overlap rate is random from contact
    // to contact (mispredicted jumps were a large share of the packing engine's step), and the
    // packing engine evaluates this for a whole block of contacts in SIMD lanes. Same products
    // as (1 +- gamma_n) k xi, bit for bit.
    const double rate = contact.overlap_rate_mps;
    const double loading = rate > 0 ? 1 + params_.gamma_n : 1.0;
    const double factor = rate < 0 ? 1 - params_.gamma_n : loading;
    return contact.overlap_m > 0 ? elastic * factor : 0.0;
  }

  // Gravity-free closed forms (the impact speed does not matter for this law). The duration is
  // a quarter period on the loading branch plus one on the unloading branch; none for gamma = 1.
  std::optional<double> ClosedFormRestitution(double effective_mass_kg, double effective_radius_m,
                                              double impact_speed_mps) const;
  std::optional<double> ClosedFormContactDuration(double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) const;
  // Explicit-integrator limit omega dt < 2 on the stiffer (loading) branch.
  double MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                            double impact_speed_mps, double gravity_mps2 = 9.81) const;
  // Most energy the law can give back while the overlap goes from its current value to 0.
  double ReturnableEnergyJ(const NormalContact& contact, const NormalHistory& history) const;
  // One impact on a plane under gravity g, in closed form (piecewise harmonic motion).
  ExactImpact SolveImpactExactly(double mass_kg, double gravity_mps2,
                                 double impact_speed_mps) const;
  // Neither LAMMPS nor LIGGGHTS has this law (LIGGGHTS' hooke/hysteresis is Luding's variant):
  // a spring-dashpot with the same e and t_c stands in.
  EngineForm ExportForm() const {
    return EngineLinearHysteresis{.stiffness_n_per_m = params_.stiffness_n_per_m,
                                  .gamma_n = params_.gamma_n};
  }

 private:
  Params params_;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_WALTON_BRAUN_H_
