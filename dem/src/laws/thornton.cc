#include "bouncecal/dem/laws/thornton.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

constexpr std::array<ParameterSpec, 2> kSpecs = {{
    {.name = "effective_modulus_pa",
     .unit = "Pa",
     .min_value = 1,
     .max_value = 1e14,
     .default_value = 1.1e11,
     .description = "E* = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2); Hertz loading up to yield and Hertz "
                    "unloading",
     .role = ParameterRole::kElastic,
     .fit = {.lower = 1, .upper = 1e14, .log_scale = true},
     .ball_dependence = BallDependence::kAlways,
     .alias = "modulus-pa"},
    // p_y / E* from 1e-5 (yields at once: e ~ 0.01 for a 1 cm steel ball at 2 m/s) to 0.5 (no
    // yield below ~ 1 km/s: elastic), in log space; the valid range stops at 2/pi.
    {.name = "yield_pressure_pa",
     .unit = "Pa",
     .min_value = 1e3,
     .max_value = 1e14,
     .default_value = 1.4e9,
     .description = "p_y: the contact pressure is capped here; beyond the yield overlap "
                    "F = F_y + pi p_y R (xi - xi_y), e = 1 below the yield speed",
     .role = ParameterRole::kDissipative,
     .fit = {.lower = 1e-5, .upper = 0.5, .log_scale = true, .relative_to = "effective_modulus_pa"},
     .ball_dependence = BallDependence::kAlways},
}};

// As for hertz (hertz.cc): a stiffening contact needs a margin on the linearised limit. The
// loading stiffens as xi^(1/2) up to yield and is linear beyond; unloading starts at the tangent
// 2 E* a_m and softens, so the margin measured for hertz covers this law too.
constexpr double kNonlinearMargin = 0.6;

// I(s) = integral_0^s (1 - x^(5/2))^(-1/2) dx, the Hertz impact's time integral (I(1) = 1.4716):
// with x = 1 - t^2 the integrand 2 t / sqrt(1 - (1 - t^2)^(5/2)) is finite on [0, 1] (2/sqrt(5/2)
// at t = 0, 2 at t = 1). Composite Simpson with 2000 intervals: the (1 - t)^(5/2)-type kink at
// t = 1 limits the error to ~ h^3.5 ~ 1e-11.
double HertzTimeIntegral(double s) {
  if (s <= 0) return 0;
  const double lower = std::sqrt(std::max(0.0, 1 - std::min(s, 1.0)));
  const auto integrand = [](double t) {
    if (t == 0) return 2 / std::sqrt(2.5);
    const double gap = -std::expm1(2.5 * std::log1p(-t * t));  // 1 - (1 - t^2)^(5/2)
    return 2 * t / std::sqrt(gap);
  };
  constexpr int kIntervals = 2000;
  const double h = (1 - lower) / kIntervals;
  double sum = integrand(lower) + integrand(1);
  for (int i = 1; i < kIntervals; ++i) sum += (i % 2 == 1 ? 4 : 2) * integrand(lower + i * h);
  return sum * h / 3;
}

}  // namespace

Thornton::Thornton(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.effective_modulus_pa, kName);
  CheckParameterValue(kSpecs[1], params.yield_pressure_pa, kName);
  // a_y / R = pi p_y / (2 E*) must stay below 1: a contact wider than the sphere never yields.
  const double limit = 2 / std::numbers::pi * params.effective_modulus_pa;
  if (params.yield_pressure_pa >= limit) {
    throw ConfigError(fmt::format(
        "thornton parameter yield_pressure_pa = {:g} is not below 2 E*/pi = {:.6g} Pa "
        "(effective_modulus_pa = {:g}): the contact would be wider than the sphere before it "
        "yields; choose a smaller yield pressure, or the hertz law for a contact that never "
        "yields",
        params.yield_pressure_pa, limit, params.effective_modulus_pa));
  }
}

Thornton::Params Thornton::FromConfig(const ContactLawConfig& config) {
  return {.effective_modulus_pa = config.Get("effective_modulus_pa"),
          .yield_pressure_pa = config.Get("yield_pressure_pa")};
}

std::span<const ParameterSpec> Thornton::Specs() { return kSpecs; }

double Thornton::LoadingWorkJ(double overlap_m, double effective_radius_m) const {
  const double yield = YieldOverlapM(effective_radius_m);
  const double stiffness = HertzStiffness(effective_radius_m);
  const double elastic = std::min(overlap_m, yield);
  double work = 0.4 * stiffness * elastic * elastic * std::sqrt(elastic);
  if (overlap_m > yield) {
    const double beyond = overlap_m - yield;
    work +=
        stiffness * yield * std::sqrt(yield) * beyond +
        0.5 * std::numbers::pi * params_.yield_pressure_pa * effective_radius_m * beyond * beyond;
  }
  return work;
}

double Thornton::YieldSpeedMps(double effective_mass_kg, double effective_radius_m) const {
  return std::sqrt(2 * LoadingWorkJ(YieldOverlapM(effective_radius_m), effective_radius_m) /
                   effective_mass_kg);
}

std::optional<double> Thornton::ClosedFormRestitution(double effective_mass_kg,
                                                      double effective_radius_m,
                                                      double impact_speed_mps) const {
  const double yield_speed = YieldSpeedMps(effective_mass_kg, effective_radius_m);
  if (!(impact_speed_mps > yield_speed)) return 1.0;
  const double u = yield_speed / impact_speed_mps;
  return std::sqrt(6 * std::sqrt(3.0) / 5) * std::sqrt(1 - u * u / 6) *
         std::pow(u / (u + 2 * std::sqrt(6.0 / 5 - u * u / 5)), 0.25);
}

std::optional<double> Thornton::ClosedFormContactDuration(double effective_mass_kg,
                                                          double effective_radius_m,
                                                          double impact_speed_mps) const {
  if (!(impact_speed_mps > 0)) return std::nullopt;
  const double m = effective_mass_kg, r = effective_radius_m, v = impact_speed_mps;
  const double stiffness = HertzStiffness(r);
  // Hertz's maximum overlap at this speed: (1/2) m v^2 = (2/5) K xi^(5/2).
  const double hertz_max = std::pow(1.25 * m * v * v / stiffness, 0.4);
  const double full = HertzTimeIntegral(1);
  const double yield = YieldOverlapM(r);
  if (hertz_max <= yield) return 2 * full * hertz_max / v;
  // Hertz loading from 0 to xi_y at speed v: t = (xi_H / v) I(xi_y / xi_H).
  const double t_elastic = hertz_max / v * HertzTimeIntegral(yield / hertz_max);
  // Plastic loading: m xi'' = -(F_y + k_p (xi - xi_y)), harmonic about xi_y - F_y / k_p, entered
  // at xi_y with the speed left after the elastic work, (1/2) m v1^2 = (1/2) m (v^2 - v_y^2).
  const double plastic_stiffness = std::numbers::pi * params_.yield_pressure_pa * r;
  const double omega = std::sqrt(plastic_stiffness / m);
  const double offset = stiffness * yield * std::sqrt(yield) / plastic_stiffness;  // F_y / k_p
  const double yield_speed = YieldSpeedMps(m, r);
  const double speed_at_yield = std::sqrt(v * v - yield_speed * yield_speed);
  const double amplitude = std::hypot(offset, speed_at_yield / omega);
  const double t_plastic = std::acos(offset / amplitude) / omega;
  const double max_overlap = yield - offset + amplitude;
  // Hertz unloading on R_p from rest at xi_m - xi_p, released at v_out, then force-free over the
  // dent xi_p at v_out.
  const Unloading branch = UnloadingFrom(max_overlap, r);
  const double recovery = max_overlap - branch.dent_m;
  const double speed_out =
      std::sqrt(0.8 * branch.stiffness * recovery * recovery * std::sqrt(recovery) / m);
  return t_elastic + t_plastic + (full * recovery + branch.dent_m) / speed_out;
}

double Thornton::MaxStableTimeStepS(double effective_mass_kg, double effective_radius_m,
                                    double impact_speed_mps, double gravity_mps2) const {
  // Deepest overlap with gravity: W(xi) = (1/2) m v^2 + m g xi, W the loading work (convex, so
  // W - m g xi falls, then rises through the root). Bracketed by doubling, then bisected.
  const double kinetic = 0.5 * effective_mass_kg * impact_speed_mps * impact_speed_mps;
  const double weight = effective_mass_kg * gravity_mps2;
  const auto excess = [&](double overlap) {
    return LoadingWorkJ(overlap, effective_radius_m) - weight * overlap - kinetic;
  };
  double high = std::max(YieldOverlapM(effective_radius_m), 1e-12);
  while (excess(high) < 0 && high < 1e3) high *= 2;
  double low = 0;
  for (int iteration = 0; iteration < 200 && high - low > 1e-15 * high; ++iteration) {
    const double middle = 0.5 * (low + high);
    (excess(middle) < 0 ? low : high) = middle;
  }
  const double tangent = 2 * params_.effective_modulus_pa * std::sqrt(effective_radius_m * high);
  return kNonlinearMargin * 2 / std::sqrt(tangent / effective_mass_kg);
}

double Thornton::ReturnableEnergyJ(const NormalContact& contact,
                                   const NormalHistory& history) const {
  if (contact.overlap_m <= 0) return 0;
  const Unloading branch =
      UnloadingFrom(std::max(history.max_overlap_m, contact.overlap_m), contact.effective_radius_m);
  const double elastic = contact.overlap_m - branch.dent_m;
  return elastic > 0 ? 0.4 * branch.stiffness * elastic * elastic * std::sqrt(elastic) : 0;
}

EngineForm Thornton::ExportForm() const {
  return NoEngineForm{
      "neither LAMMPS (pair granular: hooke, hertz, hertz/material, dmt, jkr) nor LIGGGHTS "
      "(hooke, hertz, their /stiffness forms, hooke/hysteresis) has Thornton's elastic-plastic "
      "contact, and a "
      "spring-dashpot matched at one impact speed would drop the fall of restitution with speed "
      "that is this law's point"};
}

}  // namespace bouncecal::dem
