#include "bouncecal/dem/laws/hertz_viscoelastic.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "bouncecal/dem/laws/hertz.h"

namespace bouncecal::dem {
namespace {

constexpr std::array<ParameterSpec, 2> kSpecs = {{
    {.name = "effective_modulus_pa",
     .unit = "Pa",
     .min_value = 1,
     .max_value = 1e14,
     .default_value = 1.1e11,
     .description =
         "E* = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2); elastic part (4/3) E* sqrt(R_eff) xi^(3/2)",
     .role = ParameterRole::kElastic,
     .fit = {.lower = 1, .upper = 1e14, .log_scale = true},
     .ball_dependence = BallDependence::kAlways,
     .alias = "modulus-pa"},
    // 1 ns (nearly elastic) to 0.1 ms (e ~ 0 for mm-sized balls).
    {.name = "dissipative_time_s",
     .unit = "s",
     .min_value = 0,
     .max_value = 1e-2,
     .default_value = 2e-6,
     .description =
         "Brilliantov's A: damping (3/2) A K sqrt(xi) dxi/dt; restitution falls with impact speed",
     .role = ParameterRole::kDissipative,
     .fit = {.lower = 1e-9, .upper = 1e-4, .log_scale = true},
     .ball_dependence = BallDependence::kAlways},
}};

// Ramirez et al. (1999), Phys. Rev. E 60, 4465, eq. (31)-(32).
constexpr double kC1 = 1.15344;
constexpr double kC2 = 0.79826;

}  // namespace

HertzViscoelastic::HertzViscoelastic(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.effective_modulus_pa, kName);
  CheckParameterValue(kSpecs[1], params.dissipative_time_s, kName);
}

HertzViscoelastic::Params HertzViscoelastic::FromConfig(const ContactLawConfig& config) {
  return {.effective_modulus_pa = config.Get("effective_modulus_pa"),
          .dissipative_time_s = config.Get("dissipative_time_s")};
}

std::span<const ParameterSpec> HertzViscoelastic::Specs() { return kSpecs; }

std::optional<double> HertzViscoelastic::ClosedFormRestitution(double effective_mass_kg,
                                                               double effective_radius_m,
                                                               double impact_speed_mps) const {
  // a = (3/2)^(3/2) Y sqrt(R) / (m (1 - nu^2)) in Ramirez et al.'s notation, with
  // K = (2/3) Y sqrt(R) / (1 - nu^2): a = (3/2)^(5/2) K / m.
  const double alpha = std::pow(1.5, 2.5) * Stiffness(effective_radius_m) / effective_mass_kg;
  const double x = params_.dissipative_time_s * std::pow(alpha, 0.4) *
                   std::pow(std::max(impact_speed_mps, 0.0), 0.2);
  return std::clamp(1 - kC1 * x + kC2 * x * x, 0.0, 1.0);
}

std::optional<double> HertzViscoelastic::ClosedFormContactDuration(double, double, double) const {
  return std::nullopt;
}

double HertzViscoelastic::MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                                             double impact_speed_mps, double gravity_mps2) const {
  // The elastic Hertz limit, reduced for the damping like a dashpot with the local coefficient
  // c = 1.5 A K sqrt(xi) at the deepest overlap (O'Sullivan & Bray 2004).
  const Hertz elastic({.effective_modulus_pa = params_.effective_modulus_pa});
  const double elastic_step = elastic.MaxStableTimeStepS(effective_mass_kg, effective_radius_m,
                                                         impact_speed_mps, gravity_mps2);
  const double omega = 2 / elastic_step;
  const double tangent = omega * omega * effective_mass_kg;  // 1.5 K sqrt(xi)
  const double damping = params_.dissipative_time_s * tangent;
  const double zeta = damping / (2 * effective_mass_kg * omega);
  return elastic_step * (std::sqrt(1 + zeta * zeta) - zeta);
}

double HertzViscoelastic::ReturnableEnergyJ(const NormalContact& contact,
                                            const NormalHistory&) const {
  if (contact.overlap_m <= 0) return 0;
  return 0.4 * Stiffness(contact.effective_radius_m) * contact.overlap_m * contact.overlap_m *
         std::sqrt(contact.overlap_m);
}

}  // namespace bouncecal::dem
