#include "bouncecal/dem/laws/walton_braun.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace bouncecal::dem {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr std::array<ParameterSpec, 2> kSpecs = {{
    {.name = "stiffness_n_per_m",
     .unit = "N/m",
     .min_value = 1e-3,
     .max_value = 1e15,
     .default_value = 1e7,
     .description = "normal stiffness k_n",
     .role = ParameterRole::kElastic,
     .fit = {.lower = 1e-3, .upper = 1e15, .log_scale = true},
     .alias = "stiffness-n-per-m"},
    // gamma_n = 1 never releases the ball (zero unloading stiffness), and near it the drop engine
    // spends its whole time budget; 0.98 already means eta = 0.99.
    {.name = "gamma_n",
     .unit = "1",
     .min_value = 0,
     .max_value = 1,
     .default_value = 0.5,
     .description = "hysteretic damping: loading (1+gamma_n) k_n, unloading (1-gamma_n) k_n; "
                    "eta = 2 gamma_n/(1+gamma_n)",
     .role = ParameterRole::kDissipative,
     .fit = {.lower = 0, .upper = 0.98},
     .alias = "gamma"},
}};

}  // namespace

WaltonBraun::WaltonBraun(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.stiffness_n_per_m, kName);
  CheckParameterValue(kSpecs[1], params.gamma_n, kName);
}

WaltonBraun::Params WaltonBraun::FromConfig(const ContactLawConfig& config) {
  return {.stiffness_n_per_m = config.Get("stiffness_n_per_m"), .gamma_n = config.Get("gamma_n")};
}

std::span<const ParameterSpec> WaltonBraun::Specs() { return kSpecs; }

std::optional<double> WaltonBraun::ClosedFormRestitution(double, double, double) const {
  return std::sqrt((1 - params_.gamma_n) / (1 + params_.gamma_n));
}

std::optional<double> WaltonBraun::ClosedFormContactDuration(double effective_mass_kg, double,
                                                             double) const {
  if (params_.gamma_n >= 1) return std::nullopt;
  const double k = params_.stiffness_n_per_m;
  return std::numbers::pi / 2 *
         (std::sqrt(effective_mass_kg / (k * (1 + params_.gamma_n))) +
          std::sqrt(effective_mass_kg / (k * (1 - params_.gamma_n))));
}

double WaltonBraun::MaxStableTimeStepS(double effective_mass_kg, double, double, double) const {
  return 2 * std::sqrt(effective_mass_kg / (params_.stiffness_n_per_m * (1 + params_.gamma_n)));
}

double WaltonBraun::ReturnableEnergyJ(const NormalContact& contact, const NormalHistory&) const {
  // Moving out, the force is (1-gamma) k xi; any detour deeper costs (1+gamma) k and returns less.
  if (contact.overlap_m <= 0) return 0;
  return 0.5 * params_.stiffness_n_per_m * (1 - params_.gamma_n) * contact.overlap_m *
         contact.overlap_m;
}

ExactImpact WaltonBraun::SolveImpactExactly(double mass_kg, double gravity_mps2,
                                            double impact_speed_mps) const {
  // Loading: m xi'' = -(1+gamma) k xi + m g, xi(0) = 0, xi'(0) = v: harmonic about the static
  // overlap xi_1 = g / w1^2 with amplitude sqrt(xi_1^2 + (v/w1)^2); the maximum is reached at
  // phase atan2(v/w1, -xi_1). Unloading starts at rest from xi_max: harmonic about xi_2 = g / w2^2
  // and reaches 0 only if xi_max >= 2 xi_2; otherwise the ball stays in contact and, the force
  // jumping between the branches, comes to rest in [xi_1, xi_2] after finitely many swings.
  ExactImpact impact;
  const double k = params_.stiffness_n_per_m;
  const double w1 = std::sqrt(k * (1 + params_.gamma_n) / mass_kg);
  const double xi1 = gravity_mps2 / (w1 * w1);
  const double reach = impact_speed_mps / w1;
  const double amplitude = std::hypot(xi1, reach);
  impact.max_overlap_m = xi1 + amplitude;
  const double t_load = std::atan2(reach, -xi1) / w1;
  if (params_.gamma_n >= 1) {
    impact.duration_s = kInf;
    return impact;
  }
  const double w2 = std::sqrt(k * (1 - params_.gamma_n) / mass_kg);
  const double xi2 = gravity_mps2 / (w2 * w2);
  const double swing = impact.max_overlap_m - xi2;
  if (swing < xi2) {
    impact.duration_s = kInf;
    return impact;
  }
  impact.released = true;
  impact.duration_s = t_load + std::acos(-xi2 / swing) / w2;
  impact.speed_out_mps = w2 * std::sqrt(swing * swing - xi2 * xi2);
  return impact;
}

}  // namespace bouncecal::dem
