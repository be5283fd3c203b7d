#include "bouncecal/dem/laws/hertz.h"

#include <array>
#include <cmath>
#include <numbers>

namespace bouncecal::dem {
namespace {

constexpr std::array<ParameterSpec, 1> kSpecs = {{
    {"effective_modulus_pa", "Pa", 1, 1e14, 1.1e11,
     "E* = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2); F = (4/3) E* sqrt(R_eff) xi^(3/2)"},
}};

}  // namespace

Hertz::Hertz(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.effective_modulus_pa, ToString(kKind));
}

Hertz::Params Hertz::FromConfig(const ContactLawConfig& config) {
  return {.effective_modulus_pa = config.Get("effective_modulus_pa")};
}

std::span<const ParameterSpec> Hertz::Specs() { return kSpecs; }

double Hertz::MaxOverlapM(double effective_mass_kg, double effective_radius_m,
                          double impact_speed_mps) const {
  // (1/2) m v^2 = (2/5) K xi^(5/2).
  return std::pow(1.25 * effective_mass_kg * impact_speed_mps * impact_speed_mps /
                      Stiffness(effective_radius_m),
                  0.4);
}

std::optional<double> Hertz::ClosedFormRestitution(double, double, double) const { return 1.0; }

std::optional<double> Hertz::ClosedFormContactDuration(double effective_mass_kg,
                                                       double effective_radius_m,
                                                       double impact_speed_mps) const {
  if (!(impact_speed_mps > 0)) return std::nullopt;
  const double integral =
      std::tgamma(1.4) * std::sqrt(std::numbers::pi) / std::tgamma(0.9);  // 1.47164
  return 2 * integral * MaxOverlapM(effective_mass_kg, effective_radius_m, impact_speed_mps) /
         impact_speed_mps;
}

double Hertz::MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                                 double impact_speed_mps) const {
  // Deepest overlap: the impact's plus twice the static one under 1 g (covers slow impacts and
  // the final rest); tangent stiffness dF/dxi = 1.5 K sqrt(xi).
  const double stiffness = Stiffness(effective_radius_m);
  const double static_overlap = std::pow(effective_mass_kg * 9.81 / stiffness, 2.0 / 3.0);
  const double deepest =
      MaxOverlapM(effective_mass_kg, effective_radius_m, impact_speed_mps) + 2 * static_overlap;
  return 2 / std::sqrt(1.5 * stiffness * std::sqrt(deepest) / effective_mass_kg);
}

double Hertz::ReturnableEnergyJ(const NormalContact& contact, const NormalHistory&) const {
  if (contact.overlap_m <= 0) return 0;
  return 0.4 * Stiffness(contact.effective_radius_m) * contact.overlap_m * contact.overlap_m *
         std::sqrt(contact.overlap_m);
}

}  // namespace bouncecal::dem
