#include "bouncecal/export/law_mapping.h"

#include <fmt/core.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

void RequirePositive(double value, std::string_view name, std::string_view unit) {
  if (!std::isfinite(value) || !(value > 0)) {
    throw ConfigError(
        fmt::format("{} must be a positive finite number of {}, got {}", name, unit, value));
  }
}

std::string_view EngineName(Engine engine) {
  return engine == Engine::kLammps ? "LAMMPS" : "LIGGGHTS";
}

// Maximum overlap per unit impact speed of a spring-dashpot (s): the first zero of the
// overlap rate, xi(t) = v/omega_d exp(-beta t) sin(omega_d t).
double SpringDashpotOverlapPerSpeed(const SpringDashpot& law) {
  const double beta = 0.5 * law.damping_rate_per_s;
  const double omega_d = std::numbers::pi / ContactDurationS(law);
  const double t_peak = std::atan2(omega_d, beta) / omega_d;
  return std::exp(-beta * t_peak) * std::sin(omega_d * t_peak) / omega_d;
}

// Restitution a spring-dashpot's pair coefficients give a pair of another effective mass.
double PairRestitutionAt(const SpringDashpot& pair, double effective_mass_kg) {
  SpringDashpot other = pair;
  other.effective_mass_kg = effective_mass_kg;
  return Restitution(other);
}

// The law's gravity-free closed-form restitution and contact duration, where it has them.
std::pair<std::optional<double>, std::optional<double>> ClosedForms(const dem::ContactLaw& law,
                                                                    double m_eff, double r_eff,
                                                                    double speed) {
  return {dem::ClosedFormRestitutionOf(law, m_eff, r_eff, speed),
          dem::ClosedFormContactDurationOf(law, m_eff, r_eff, speed)};
}

// The laws MapContactLaw maps at their default parameters for this ball and speed, for messages.
std::string ExportableLawNames(double ball_mass_kg, double ball_radius_m, double speed) {
  std::string names;
  for (dem::ContactLawKind kind : dem::kAllContactLawKinds) {
    const dem::ContactLaw law = dem::MakeContactLaw({.kind = kind, .parameters = {}});
    const dem::EngineForm form = dem::ExportFormOf(law);
    if (std::holds_alternative<dem::NoEngineForm>(form)) continue;
    if (std::holds_alternative<dem::EngineMatchAtSpeed>(form)) {
      const auto [wall_e, wall_t] = ClosedForms(law, ball_mass_kg, ball_radius_m, speed);
      const auto [pair_e, pair_t] =
          ClosedForms(law, 0.5 * ball_mass_kg, 0.5 * ball_radius_m, speed);
      if (!wall_e || !wall_t || !pair_e || !pair_t) continue;
    }
    if (!names.empty()) names += ", ";
    names += dem::ToString(kind);
  }
  return names;
}

}  // namespace

LawMapping MapWaltonBraun(double stiffness_n_per_m, double gamma_n, double ball_mass_kg,
                          Engine engine) {
  RequirePositive(stiffness_n_per_m, "stiffness_n_per_m", "N/m");
  RequirePositive(ball_mass_kg, "ball mass", "kilograms");
  if (!std::isfinite(gamma_n) || gamma_n < 0 || gamma_n >= 1) {
    throw ConfigError(fmt::format(
        "walton-braun gamma_n = {} cannot be exported: it must be in [0, 1) (gamma_n = 1 never "
        "rebounds, and no finite spring-dashpot matches that)",
        gamma_n));
  }
  const double e = std::sqrt((1 - gamma_n) / (1 + gamma_n));
  auto duration = [&](double m_eff) {
    return 0.5 * std::numbers::pi * std::sqrt(m_eff / stiffness_n_per_m) *
           (1 / std::sqrt(1 + gamma_n) + 1 / std::sqrt(1 - gamma_n));
  };
  LawMapping mapping;
  mapping.source_law = "walton-braun";
  mapping.source_description =
      fmt::format("walton-braun (stiffness_n_per_m = {:.6g} N/m, gamma_n = {:.6g})",
                  stiffness_n_per_m, gamma_n);
  mapping.exact = false;
  mapping.restitution = e;
  mapping.wall_contact_duration_s = duration(ball_mass_kg);
  mapping.pair_contact_duration_s = duration(0.5 * ball_mass_kg);
  mapping.wall = MatchRestitutionAndDuration(e, mapping.wall_contact_duration_s, ball_mass_kg);
  mapping.pair =
      MatchRestitutionAndDuration(e, mapping.pair_contact_duration_s, 0.5 * ball_mass_kg);

  const double card_overlap_per_speed =
      std::sqrt(ball_mass_kg / (stiffness_n_per_m * (1 + gamma_n)));
  const double mapped_overlap_per_speed = SpringDashpotOverlapPerSpeed(mapping.wall);
  mapping.notes = {
      fmt::format(
          "MAPPED LAW: {} has no Walton-Braun hysteretic law{}, so this deck uses the linear "
          "spring-dashpot with the SAME restitution e = {:.6f} and the SAME contact duration "
          "(wall {:.4g} s, equal-sphere pair {:.4g} s). Both laws are linear, so e and t_c match "
          "at every impact speed.",
          EngineName(engine),
          engine == Engine::kLiggghts
              ? " (hooke/hysteresis is Luding's variant, whose e depends on impact speed)"
              : "",
          e, mapping.wall_contact_duration_s, mapping.pair_contact_duration_s),
      fmt::format("Wall contacts (sphere on plane, m_eff = m = {:.6g} kg): kn = {:.6g} N/m, "
                  "gamma_n = {:.6g} 1/s (damping coefficient m_eff gamma_n).",
                  ball_mass_kg, mapping.wall.stiffness_n_per_m, mapping.wall.damping_rate_per_s),
      fmt::format("Pair contacts (two equal spheres, m_eff = m/2): kn = {:.6g} N/m (unchanged), "
                  "gamma_n = {:.6g} 1/s (sqrt(2) x wall), so equal spheres collide with the same e "
                  "and the card law's pair t_c.",
                  mapping.pair.stiffness_n_per_m, mapping.pair.damping_rate_per_s),
      fmt::format(
          "What still differs: the force history inside a contact (the dashpot force jumps to "
          "m_eff gamma_n v at touch and turns attractive just before separation; the card's law "
          "jumps from (1+g)k xi to (1-g)k xi at maximum compression): maximum overlap {:.4g} vs "
          "{:.4g} m per m/s of impact speed ({:+.1f} %). Unequal spheres get e = {:.4f} at "
          "m_eff = m and {:.4f} at m_eff = m/4 from the pair coefficients instead of {:.4f}.",
          mapped_overlap_per_speed, card_overlap_per_speed,
          100 * (mapped_overlap_per_speed / card_overlap_per_speed - 1),
          PairRestitutionAt(mapping.pair, ball_mass_kg),
          PairRestitutionAt(mapping.pair, 0.25 * ball_mass_kg), e),
  };
  return mapping;
}

LawMapping MapLinearDashpot(double stiffness_n_per_m, double damping_ratio, double ball_mass_kg,
                            Engine engine) {
  RequirePositive(stiffness_n_per_m, "stiffness_n_per_m", "N/m");
  RequirePositive(ball_mass_kg, "ball mass", "kilograms");
  if (!std::isfinite(damping_ratio) || damping_ratio < 0 || damping_ratio >= 1) {
    throw ConfigError(
        fmt::format("linear-dashpot damping_ratio = {} cannot be exported: it must be in [0, 1) (a "
                    "critically or overdamped contact never rebounds)",
                    damping_ratio));
  }
  auto law_for = [&](double m_eff) {
    return SpringDashpot{stiffness_n_per_m,
                         2 * damping_ratio * std::sqrt(stiffness_n_per_m / m_eff), m_eff};
  };
  LawMapping mapping;
  mapping.source_law = "linear-dashpot";
  mapping.source_description =
      fmt::format("linear-dashpot (stiffness_n_per_m = {:.6g} N/m, damping_ratio = {:.6g})",
                  stiffness_n_per_m, damping_ratio);
  mapping.exact = true;
  mapping.wall = law_for(ball_mass_kg);
  mapping.pair = law_for(0.5 * ball_mass_kg);
  mapping.restitution = Restitution(mapping.wall);
  mapping.wall_contact_duration_s = ContactDurationS(mapping.wall);
  mapping.pair_contact_duration_s = ContactDurationS(mapping.pair);
  mapping.notes = {
      fmt::format("EXACT LAW: {}'s linear spring-dashpot is the card's law (damping coefficient "
                  "2 zeta sqrt(m_eff k) = m_eff gamma_n); e = {:.6f}, t_c = {:.4g} s on the wall.",
                  EngineName(engine), mapping.restitution, mapping.wall_contact_duration_s),
      fmt::format("Wall contacts (m_eff = m = {:.6g} kg): gamma_n = {:.6g} 1/s; pair contacts "
                  "(m_eff = m/2): gamma_n = {:.6g} 1/s. Pairs of unequal spheres get a slightly "
                  "different damping ratio than the card's, since one gamma_n serves every pair.",
                  ball_mass_kg, mapping.wall.damping_rate_per_s, mapping.pair.damping_rate_per_s),
  };
  return mapping;
}

LawMapping MapContactLaw(const dem::ContactLawConfig& law, double ball_mass_kg,
                         double ball_radius_m, double reference_impact_speed_mps, Engine engine) {
  RequirePositive(ball_mass_kg, "ball mass", "kilograms");
  RequirePositive(ball_radius_m, "ball radius", "metres");
  RequirePositive(reference_impact_speed_mps, "reference impact speed", "m/s");
  const dem::ContactLaw built = dem::MakeContactLaw(law);  // validates, ConfigError if bad
  const std::string name(dem::ToString(law.kind));
  const dem::EngineForm form = dem::ExportFormOf(built);
  if (const auto* hysteresis = std::get_if<dem::EngineLinearHysteresis>(&form)) {
    return MapWaltonBraun(hysteresis->stiffness_n_per_m, hysteresis->gamma_n, ball_mass_kg, engine);
  }
  if (const auto* dashpot = std::get_if<dem::EngineSpringDashpot>(&form)) {
    return MapLinearDashpot(dashpot->stiffness_n_per_m, dashpot->damping_ratio, ball_mass_kg,
                            engine);
  }
  if (const auto* none = std::get_if<dem::NoEngineForm>(&form)) {
    throw ConfigError(
        fmt::format("contact law '{}' cannot be exported to {}: {}; laws that can be exported "
                    "(fit one of them to the same recordings): {}",
                    name, EngineName(engine), none->reason,
                    ExportableLawNames(ball_mass_kg, ball_radius_m, reference_impact_speed_mps)));
  }
  const double v = reference_impact_speed_mps;
  const auto [wall_e, wall_t] = ClosedForms(built, ball_mass_kg, ball_radius_m, v);
  const auto [pair_e, pair_t] = ClosedForms(built, 0.5 * ball_mass_kg, 0.5 * ball_radius_m, v);
  if (!wall_e || !wall_t || !pair_e || !pair_t) {
    throw ConfigError(fmt::format(
        "contact law '{}' has no closed-form restitution and contact duration, so it cannot be "
        "mapped to {} with equal e and t_c; laws that can be exported: {}",
        name, EngineName(engine),
        ExportableLawNames(ball_mass_kg, ball_radius_m, reference_impact_speed_mps)));
  }
  LawMapping mapping;
  mapping.source_law = name;
  std::string parameters;
  for (const auto& spec : dem::ParameterSpecs(law.kind)) {
    parameters +=
        fmt::format("{}{} = {:.6g}", parameters.empty() ? "" : ", ", spec.name, law.Get(spec.name));
  }
  mapping.source_description = fmt::format("{} ({})", name, parameters);
  mapping.exact = false;
  mapping.restitution = *wall_e;
  mapping.wall_contact_duration_s = *wall_t;
  mapping.pair_contact_duration_s = *pair_t;
  mapping.wall = MatchRestitutionAndDuration(*wall_e, *wall_t, ball_mass_kg);
  mapping.pair = MatchRestitutionAndDuration(*pair_e, *pair_t, 0.5 * ball_mass_kg);

  const auto slow = ClosedForms(built, ball_mass_kg, ball_radius_m, 0.25 * v);
  const auto fast = ClosedForms(built, ball_mass_kg, ball_radius_m, 4 * v);
  const bool speed_independent =
      slow.first && fast.first && slow.second && fast.second &&
      std::abs(*slow.first - *wall_e) < 1e-9 && std::abs(*fast.first - *wall_e) < 1e-9 &&
      std::abs(*slow.second / *wall_t - 1) < 1e-9 && std::abs(*fast.second / *wall_t - 1) < 1e-9;
  mapping.notes.push_back(fmt::format(
      "MAPPED LAW: bouncecal has no exact {} form of '{}' (yet), so this deck uses the linear "
      "spring-dashpot with the SAME restitution e = {:.6f} and the SAME contact duration (wall "
      "{:.4g} s, equal-sphere pair {:.4g} s) at the reference impact speed {:.4g} m/s.",
      EngineName(engine), name, *wall_e, *wall_t, *pair_t, v));
  if (speed_independent) {
    mapping.notes.push_back(
        "The card's law has a speed-independent e and t_c, like the spring-dashpot, so they match "
        "at every impact speed.");
  } else {
    mapping.notes.push_back(fmt::format(
        "DEVIATION: the card's law depends on the impact speed (wall e = {} at {:.3g} m/s and {} "
        "at {:.3g} m/s; t_c = {} and {} s) while the spring-dashpot keeps e = {:.4f} and t_c = "
        "{:.4g} s at every speed.",
        slow.first ? fmt::format("{:.4f}", *slow.first) : "?", 0.25 * v,
        fast.first ? fmt::format("{:.4f}", *fast.first) : "?", 4 * v,
        slow.second ? fmt::format("{:.4g}", *slow.second) : "?",
        fast.second ? fmt::format("{:.4g}", *fast.second) : "?", *wall_e, *wall_t));
  }
  mapping.notes.push_back(fmt::format(
      "Wall contacts (m_eff = m = {:.6g} kg): kn = {:.6g} N/m, gamma_n = {:.6g} 1/s. Pair "
      "contacts (m_eff = m/2): kn = {:.6g} N/m, gamma_n = {:.6g} 1/s. Pairs of unequal spheres get "
      "neither coefficient set exactly right.",
      ball_mass_kg, mapping.wall.stiffness_n_per_m, mapping.wall.damping_rate_per_s,
      mapping.pair.stiffness_n_per_m, mapping.pair.damping_rate_per_s));
  return mapping;
}

}  // namespace bouncecal::calibrate
