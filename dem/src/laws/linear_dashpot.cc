#include "bouncecal/dem/laws/linear_dashpot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr std::array<ParameterSpec, 2> kSpecs = {{
    {.name = "stiffness_n_per_m",
     .unit = "N/m",
     .min_value = 1e-3,
     .max_value = 1e15,
     .default_value = 1e7,
     .description = "normal stiffness k",
     .role = ParameterRole::kElastic,
     .fit = {.lower = 1e-3, .upper = 1e15, .log_scale = true},
     .alias = "stiffness-n-per-m"},
    // zeta -> 1 is critical damping, which never releases the ball.
    {.name = "damping_ratio",
     .unit = "1",
     .min_value = 0,
     .max_value = 1,
     .default_value = 0.1722,
     .description =
         "zeta: damping coefficient 2 zeta sqrt(m_eff k); e = exp(-pi zeta/sqrt(1-zeta^2))",
     .role = ParameterRole::kDissipative,
     .fit = {.lower = 0, .upper = 0.95},
     .alias = "gamma"},
}};

}  // namespace

LinearDashpot::LinearDashpot(const Params& params) : params_(params) {
  CheckParameterValue(kSpecs[0], params.stiffness_n_per_m, kName);
  CheckParameterValue(kSpecs[1], params.damping_ratio, kName);
}

LinearDashpot::Params LinearDashpot::FromConfig(const ContactLawConfig& config) {
  return {.stiffness_n_per_m = config.Get("stiffness_n_per_m"),
          .damping_ratio = config.Get("damping_ratio")};
}

std::span<const ParameterSpec> LinearDashpot::Specs() { return kSpecs; }

double LinearDashpot::DampingRatioForRestitution(double restitution) {
  if (!(restitution > 0 && restitution <= 1)) {
    throw ConfigError("linear-dashpot: a restitution for the damping ratio must lie in (0, 1]");
  }
  const double log_e = std::log(restitution);
  return -log_e / std::sqrt(std::numbers::pi * std::numbers::pi + log_e * log_e);
}

std::optional<double> LinearDashpot::ClosedFormRestitution(double, double, double) const {
  const double zeta = params_.damping_ratio;
  if (zeta >= 1) return 0.0;
  return std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));
}

std::optional<double> LinearDashpot::ClosedFormContactDuration(double effective_mass_kg, double,
                                                               double) const {
  const double zeta = params_.damping_ratio;
  if (zeta >= 1) return std::nullopt;
  const double omega = std::sqrt(params_.stiffness_n_per_m / effective_mass_kg);
  return std::numbers::pi / (omega * std::sqrt(1 - zeta * zeta));
}

double LinearDashpot::MaxStableTimeStepS(double effective_mass_kg, double, double, double) const {
  const double zeta = params_.damping_ratio;
  const double omega = std::sqrt(params_.stiffness_n_per_m / effective_mass_kg);
  return 2 / omega * (std::sqrt(1 + zeta * zeta) - zeta);
}

double LinearDashpot::ReturnableEnergyJ(const NormalContact& contact, const NormalHistory&) const {
  // The dashpot only ever removes energy, so the spring's store is the bound.
  if (contact.overlap_m <= 0) return 0;
  return 0.5 * params_.stiffness_n_per_m * contact.overlap_m * contact.overlap_m;
}

ExactImpact LinearDashpot::SolveImpactExactly(double mass_kg, double gravity_mps2,
                                              double impact_speed_mps) const {
  // m xi'' = -k xi - c xi' + m g: a damped oscillator about xi_s = g/w^2,
  //   xi(t) = xi_s + exp(-a t) (A cos(w_d t) + B sin(w_d t)),  a = zeta w,
  // with A = -xi_s, B = (v - a xi_s)/w_d. xi' = exp(-a t)(P cos + Q sin) with P = v and
  // Q = w_d xi_s - a B vanishes first at the maximum (phase theta_1 = atan2(P, -Q)), then at the
  // minimum half a period later. The ball leaves iff xi(minimum) <= 0; the root between the two is
  // found by bisection-safeguarded Newton, converging to machine precision in a few steps.
  // Critical damping crosses the static overlap at most once, so it never releases the ball.
  ExactImpact impact;
  impact.duration_s = kInf;
  const double zeta = params_.damping_ratio;
  const double w = std::sqrt(params_.stiffness_n_per_m / mass_kg);
  const double xi_s = gravity_mps2 / (w * w);
  if (zeta >= 1) {
    // xi = xi_s + exp(-w t)(A + B t), A = -xi_s, B = v - w xi_s; maximum where xi' = 0.
    const double b = impact_speed_mps - w * xi_s;
    if (b <= 0) {  // so slow that it creeps monotonically into the static overlap
      impact.max_overlap_m = xi_s;
      return impact;
    }
    const double t_max = (b + w * xi_s) / (w * b);
    impact.max_overlap_m = xi_s + std::exp(-w * t_max) * (-xi_s + b * t_max);
    return impact;
  }
  const double a = zeta * w;
  const double wd = w * std::sqrt(1 - zeta * zeta);
  const double amp_a = -xi_s;
  const double amp_b = (impact_speed_mps - a * xi_s) / wd;
  const double p = impact_speed_mps;
  const double q = wd * xi_s - a * amp_b;
  // Overlap and its rate share one exponential and one sine/cosine pair.
  const auto evaluate = [&](double t, double& overlap, double& rate) {
    const double decay = std::exp(-a * t);
    const double c = std::cos(wd * t), s = std::sin(wd * t);
    overlap = xi_s + decay * (amp_a * c + amp_b * s);
    rate = decay * (p * c + q * s);
  };
  const double theta_max = std::atan2(p, -q);
  double lo = theta_max / wd;
  double hi = (theta_max + std::numbers::pi) / wd;
  double value = 0, slope = 0;
  evaluate(lo, impact.max_overlap_m, slope);
  // xi decreases monotonically on [lo, hi]; it is released iff xi(hi) <= 0. Newton from the
  // gravity-free root pi / w_d (gravity moves it by a fraction g / (w v) of the contact),
  // safeguarded by bisection; xi(hi) itself is only needed when the iteration runs into hi.
  double t = std::clamp(std::numbers::pi / wd, lo, hi);
  bool converged = false, root = false;
  for (int iteration = 0; iteration < 200 && !converged; ++iteration) {
    evaluate(t, value, slope);
    if (value > 0) {
      lo = t;
    } else {
      hi = t;
    }
    if (slope < 0 && std::abs(value / slope) <= 1e-14 * t) {
      t -= value / slope;
      converged = root = true;
    } else {
      double next = slope < 0 ? t - value / slope : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      t = next;
      converged = hi - lo <= 1e-14 * hi;
    }
  }
  if (!root && value > 0) return impact;  // ran into the minimum without crossing: stays
  impact.released = true;
  impact.duration_s = t;
  impact.speed_out_mps = -slope;
  return impact;
}

}  // namespace bouncecal::dem
