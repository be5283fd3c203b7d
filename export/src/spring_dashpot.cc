#include "bouncecal/export/spring_dashpot.h"

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// omega_d^2 = k/m_eff - beta^2; <= 0 means no oscillation, hence no rebound.
double DampedFrequencySquared(const SpringDashpot& law) {
  const double beta = 0.5 * law.damping_rate_per_s;
  return law.stiffness_n_per_m / law.effective_mass_kg - beta * beta;
}

}  // namespace

double Restitution(const SpringDashpot& law) {
  const double omega_d_squared = DampedFrequencySquared(law);
  if (!(omega_d_squared > 0)) return 0;
  const double beta = 0.5 * law.damping_rate_per_s;
  return std::exp(-beta * std::numbers::pi / std::sqrt(omega_d_squared));
}

double ContactDurationS(const SpringDashpot& law) {
  const double omega_d_squared = DampedFrequencySquared(law);
  if (!(omega_d_squared > 0)) return std::numeric_limits<double>::infinity();
  return std::numbers::pi / std::sqrt(omega_d_squared);
}

SpringDashpot MatchRestitutionAndDuration(double restitution, double contact_duration_s,
                                          double effective_mass_kg) {
  if (!std::isfinite(restitution) || !(restitution > 0) || restitution > 1) {
    throw ConfigError(fmt::format(
        "restitution {} cannot be matched by a spring-dashpot; it must be in (0, 1] (a law "
        "that never rebounds has no finite-damping equivalent)",
        restitution));
  }
  if (!std::isfinite(contact_duration_s) || !(contact_duration_s > 0)) {
    throw ConfigError(fmt::format(
        "contact duration {} s cannot be matched; it must be a positive finite number of seconds",
        contact_duration_s));
  }
  if (!std::isfinite(effective_mass_kg) || !(effective_mass_kg > 0)) {
    throw ConfigError(fmt::format(
        "effective mass {} kg cannot be used; it must be a positive finite number of kilograms",
        effective_mass_kg));
  }
  const double beta = -std::log(restitution) / contact_duration_s;
  const double omega_d = std::numbers::pi / contact_duration_s;
  SpringDashpot law;
  law.effective_mass_kg = effective_mass_kg;
  law.stiffness_n_per_m = effective_mass_kg * (omega_d * omega_d + beta * beta);
  law.damping_rate_per_s = 2 * beta;
  return law;
}

}  // namespace bouncecal::calibrate
