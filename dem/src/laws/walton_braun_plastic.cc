#include "bouncecal/dem/laws/walton_braun_plastic.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr std::array<ParameterSpec, 3> kSpecs = {{
    {.name = "stiffness_n_per_m",
     .unit = "N/m",
     .min_value = 1e-3,
     .max_value = 1e15,
     .default_value = 1e7,
     .description = "loading stiffness k1",
     .role = ParameterRole::kElastic,
     .fit = {.lower = 1e-3, .upper = 1e15, .log_scale = true},
     .alias = "stiffness-n-per-m"},
    // e = sqrt(k1/k2): [k1, 1e4 k1] covers e from 1 down to 0.01.
    {.name = "unloading_stiffness_n_per_m",
     .unit = "N/m",
     .min_value = 1e-3,
     .max_value = 1e15,
     .default_value = 3e7,
     .description = "unloading stiffness k2 >= k1 from the maximum overlap; e = sqrt(k1/k2)",
     .role = ParameterRole::kDissipative,
     .fit =
         {.lower = 1 + 1e-9, .upper = 1e4, .log_scale = true, .relative_to = "stiffness_n_per_m"}},
    // Opt-in: the default 0 is the 1986 form, and a second fitted parameter needs a sequence with
    // many impacts. Impact overlaps of mm-to-cm balls are 1e-6 to 1e-4 m; the range is linear to
    // include 0.
    {.name = "plastic_flow_overlap_m",
     .unit = "m",
     .min_value = 0,
     .max_value = 1,
     .default_value = 0,
     .description =
         "Luding: k2 grows linearly with the maximum overlap up to this overlap; 0 = constant k2",
     .role = ParameterRole::kOptIn,
     .fit = {.lower = 0, .upper = 1e-3},
     .ball_dependence = BallDependence::kWhenUsed},
}};

}  // namespace

WaltonBraunPlastic::WaltonBraunPlastic(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.stiffness_n_per_m, kName);
  CheckParameterValue(kSpecs[1], params.unloading_stiffness_n_per_m, kName);
  CheckParameterValue(kSpecs[2], params.plastic_flow_overlap_m, kName);
  if (params.unloading_stiffness_n_per_m < params.stiffness_n_per_m) {
    throw ConfigError(fmt::format(
        "walton-braun-plastic parameter unloading_stiffness_n_per_m = {} is below "
        "stiffness_n_per_m = {}; the valid range is [stiffness_n_per_m, 1e+15] N/m (k2 = k1 is "
        "elastic)",
        params.unloading_stiffness_n_per_m, params.stiffness_n_per_m));
  }
}

WaltonBraunPlastic::Params WaltonBraunPlastic::FromConfig(const ContactLawConfig& config) {
  return {.stiffness_n_per_m = config.Get("stiffness_n_per_m"),
          .unloading_stiffness_n_per_m = config.Get("unloading_stiffness_n_per_m"),
          .plastic_flow_overlap_m = config.Get("plastic_flow_overlap_m")};
}

std::span<const ParameterSpec> WaltonBraunPlastic::Specs() { return kSpecs; }

std::optional<double> WaltonBraunPlastic::ClosedFormRestitution(double effective_mass_kg, double,
                                                                double impact_speed_mps) const {
  const double max_overlap =
      impact_speed_mps * std::sqrt(effective_mass_kg / params_.stiffness_n_per_m);
  return std::sqrt(params_.stiffness_n_per_m / UnloadingStiffness(max_overlap));
}

std::optional<double> WaltonBraunPlastic::ClosedFormContactDuration(double effective_mass_kg,
                                                                    double,
                                                                    double impact_speed_mps) const {
  // Loading quarter period, unloading quarter period down to xi_0, then force-free flight from
  // xi_0 = xi_max (1 - e^2) at the release speed e v: xi_0 / (e v) = sqrt(m/k1) (1 - e^2) / e.
  const double k1 = params_.stiffness_n_per_m;
  const double t1 = std::sqrt(effective_mass_kg / k1);
  const double k2 = UnloadingStiffness(impact_speed_mps * t1);
  const double e2 = k1 / k2;
  return std::numbers::pi / 2 * (t1 + std::sqrt(effective_mass_kg / k2)) +
         t1 * (1 - e2) / std::sqrt(e2);
}

double WaltonBraunPlastic::MaxStableTimeStepS(double effective_mass_kg, double, double,
                                              double) const {
  return 2 * std::sqrt(effective_mass_kg / params_.unloading_stiffness_n_per_m);
}

double WaltonBraunPlastic::ReturnableEnergyJ(const NormalContact& contact,
                                             const NormalHistory& history) const {
  if (contact.overlap_m <= 0) return 0;
  const double max_overlap = std::max(history.max_overlap_m, contact.overlap_m);
  const double k2 = UnloadingStiffness(max_overlap);
  const double elastic = contact.overlap_m - max_overlap * (1 - params_.stiffness_n_per_m / k2);
  return elastic > 0 ? 0.5 * k2 * elastic * elastic : 0;
}

ExactImpact WaltonBraunPlastic::SolveImpactExactly(double mass_kg, double gravity_mps2,
                                                   double impact_speed_mps) const {
  // Loading as a harmonic oscillator on k1 about g/w1^2; unloading on k2 about xi_0 + g/w2^2 from
  // rest at xi_max; from xi_0 up to the surface the ball flies freely. On the k2 branch the
  // motion is elastic, so a ball that cannot reach xi_0, or cannot climb from xi_0 to 0, stays
  // trapped for ever: at rest in its dent.
  ExactImpact impact;
  const double k1 = params_.stiffness_n_per_m;
  const double w1 = std::sqrt(k1 / mass_kg);
  const double xi1 = gravity_mps2 / (w1 * w1);
  const double reach = impact_speed_mps / w1;
  impact.max_overlap_m = xi1 + std::hypot(xi1, reach);
  const double k2 = UnloadingStiffness(impact.max_overlap_m);
  const double t_load = std::atan2(reach, -xi1) / w1;
  const double offset = impact.max_overlap_m * (1 - k1 / k2);
  const double w2 = std::sqrt(k2 / mass_kg);
  const double xi2 = gravity_mps2 / (w2 * w2);
  const double swing = impact.max_overlap_m - offset - xi2;
  impact.duration_s = kInf;
  if (swing < xi2) return impact;
  const double t_unload = std::acos(-xi2 / swing) / w2;
  const double speed_at_offset = w2 * std::sqrt(swing * swing - xi2 * xi2);
  const double climb = speed_at_offset * speed_at_offset - 2 * gravity_mps2 * offset;
  if (climb < 0) return impact;
  impact.released = true;
  impact.speed_out_mps = std::sqrt(climb);
  const double t_free = gravity_mps2 > 0 ? (speed_at_offset - impact.speed_out_mps) / gravity_mps2
                                         : offset / speed_at_offset;
  impact.duration_s = t_load + t_unload + t_free;
  return impact;
}

}  // namespace bouncecal::dem
