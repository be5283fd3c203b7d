#include "engine/contact_limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "engine/van_der_waals.h"

namespace bouncecal::dem::scene {

namespace {

// Solid spheres (2D disks are spheres in a plane here too): I = 2/5 m r^2, so a tangential
// push at the surface also spins the sphere up, r^2 / I = 2.5 / m more compliance per sphere.
constexpr double kSurfaceSpinCompliance = 2.5;

}  // namespace

TimeStepLimits SceneTimeStepLimits(const Scene& scene, const BodyExtremes& bodies) {
  const auto law = MakeContactLaw(scene.material.law);
  const double g = scene.gravity_mps2;
  const auto& v0 = scene.insertion.initial_velocity_mps;
  const double launch2 = v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2];
  const double impact_speed =
      std::sqrt(launch2 + 2 * std::max(g, 0.0) * std::max(bodies.highest_top_m, 0.0));

  struct Body {
    double mass_kg;
    double radius_m;
  };
  const Body lightest{bodies.lightest_mass_kg, bodies.lightest_radius_m};
  const Body largest{bodies.largest_mass_kg, bodies.largest_radius_m};
  TimeStepLimits limits{{std::numeric_limits<double>::infinity(), ""},
                        {std::numeric_limits<double>::infinity(), ""}};
  auto consider = [](TimeStepLimit& best, double limit_s, std::string what) {
    if (limit_s < best.limit_s) best = {limit_s, std::move(what)};
  };
  // wall: a body of infinite mass and radius (m_eff = m, R_eff = r).
  auto contact = [&](const Body& a, const Body* b, const char* name) {
    const double m_eff = b ? a.mass_kg * b->mass_kg / (a.mass_kg + b->mass_kg) : a.mass_kg;
    const double r_eff = b ? a.radius_m * b->radius_m / (a.radius_m + b->radius_m) : a.radius_m;
    const double normal_limit = std::visit(
        [&](const auto& typed) { return typed.MaxStableTimeStepS(m_eff, r_eff, impact_speed, g); },
        law);
    consider(limits.normal, normal_limit, fmt::format("{} normal contact", name));
    if (scene.physics.tangential) {
      const double spin = scene.physics.rotation ? kSurfaceSpinCompliance : 0.0;
      const double compliance =
          b ? (1 + spin) / a.mass_kg + (1 + spin) / b->mass_kg : (1 + spin) / a.mass_kg;
      consider(limits.tangential,
               2 / std::sqrt(scene.material.tangential_stiffness_n_per_m * compliance),
               fmt::format("{} tangential spring", name));
    }
  };
  contact(lightest, &lightest, "smallest particle pair");
  contact(lightest, &largest, "smallest-largest particle pair");
  contact(largest, &largest, "largest particle pair");
  contact(lightest, nullptr, "smallest particle on a wall");
  contact(largest, nullptr, "largest particle on a wall");
  return limits;
}

TimeStepLimits CheckTimeStep(const Scene& scene, const BodyExtremes& bodies, bool allow_unstable,
                             std::vector<std::string>& warnings, std::vector<std::string>& notes) {
  const TimeStepLimits limits = SceneTimeStepLimits(scene, bodies);
  // Above half a limit is a choice a scene may make knowingly, and then says why.
  const bool explained = !scene.time_step_reason.empty();
  const auto above_half = [&](std::string text) {
    if (explained) {
      notes.push_back(std::move(text) + "; kept, as the scene says: " + scene.time_step_reason);
    } else {
      warnings.push_back(std::move(text));
    }
  };
  const double dt = scene.time_step_s;
  const TimeStepLimit& normal = limits.normal;
  if (dt > normal.limit_s && !allow_unstable) {
    throw ConfigError(fmt::format(
        "{}: time_step_s = {:.3g} s exceeds {:.3g} s, the stability limit of the stiffest contact "
        "({}); use a step of at most {:.3g} s (half the limit: several contacts on one particle "
        "stiffen a pack), softer contacts or heavier particles",
        scene.source.string(), dt, normal.limit_s, normal.stiffest,
        kSafeFractionOfLimit * normal.limit_s));
  }
  if (dt > kSafeFractionOfLimit * normal.limit_s) {
    above_half(fmt::format(
        "time_step_s = {:.3g} s is {:.2f} of {:.3g} s, the stability limit of one {}: a particle "
        "held by several contacts is stiffer than one, and packs have blown up from about 0.8 of "
        "it; at most {:.3g} s is safe",
        dt, dt / normal.limit_s, normal.limit_s, normal.stiffest,
        kSafeFractionOfLimit * normal.limit_s));
  }
  const TimeStepLimit& tangential = limits.tangential;
  if (dt > tangential.limit_s) {
    warnings.push_back(fmt::format(
        "time_step_s = {:.3g} s exceeds {:.3g} s, the stability limit of the {}: sticking "
        "contacts will oscillate until they slide (friction caps them, so the run goes on); use "
        "at most {:.3g} s, or a softer tangential_stiffness_n_per_m, to resolve them",
        dt, tangential.limit_s, tangential.stiffest, kSafeFractionOfLimit * tangential.limit_s));
  } else if (dt > kSafeFractionOfLimit * tangential.limit_s) {
    above_half(fmt::format(
        "time_step_s = {:.3g} s is {:.2f} of {:.3g} s, the stability limit of the {}: sticking "
        "contacts are resolved by too few steps and slip, so packs settle denser than with a "
        "finer step (measured 0.004-0.03 denser, mean coordination up by 0.1-1, at 0.65-0.8 of "
        "it); at most {:.3g} s resolves them",
        dt, dt / tangential.limit_s, tangential.limit_s, tangential.stiffest,
        kSafeFractionOfLimit * tangential.limit_s));
  }
  return limits;
}

std::optional<std::string> VanDerWaalsOverlapProblem(const Scene& scene,
                                                     const BodyExtremes& bodies) {
  if (!scene.physics.van_der_waals) return std::nullopt;
  const auto law = MakeContactLaw(scene.material.law);
  const double h = scene.material.vdw_min_gap_m;
  for (const double radius_m : {bodies.lightest_radius_m, bodies.largest_radius_m}) {
    const double r_eff = radius_m / 2;
    const double pull_n = VanDerWaalsForceN(0.0, r_eff, scene.material.hamaker_j, h);  // at contact
    const NormalContact deep{kMaxVanDerWaalsOverlap * r_eff, 0, bodies.lightest_mass_kg / 2, r_eff};
    NormalHistory fresh{};
    const double push_n =
        std::visit([&](const auto& typed) { return typed.NormalForce(deep, fresh); }, law);
    if (push_n < pull_n) {
      return fmt::format(
          "van der Waals at vdw_min_gap_m = {:.3g} m pulls two particles of radius {:.3g} m "
          "together with {:.3g} N, more than the contact law pushes back at an overlap of {:.0f} "
          "% of their effective radius ({:.3g} N); raise vdw_min_gap_m (interatomic distances are "
          "~4e-10 m) or stiffen the contacts",
          h, radius_m, pull_n, 100 * kMaxVanDerWaalsOverlap, push_n);
    }
  }
  return std::nullopt;
}

}  // namespace bouncecal::dem::scene
