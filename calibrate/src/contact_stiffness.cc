#include "bouncecal/calibrate/contact_stiffness.h"

#include <fmt/core.h>

#include <cmath>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

const dem::ParameterSpec& ElasticSpec(dem::ContactLawKind kind) {
  for (const auto& spec : dem::ParameterSpecs(kind)) {
    if (spec.alias == "stiffness-n-per-m" || spec.alias == "modulus-pa") return spec;
  }
  throw ConfigError(
      fmt::format("the {} law has no stiffness or modulus to set from a contact "
                  "duration",
                  dem::ToString(kind)));
}

// "0.24 ms", "70.8 us": durations as people read them.
std::string Duration(double seconds) {
  if (seconds >= 1e-3) return fmt::format("{:.3g} ms", seconds * 1e3);
  return fmt::format("{:.3g} us", seconds * 1e6);
}

}  // namespace

std::string_view ElasticParameterName(dem::ContactLawKind kind) { return ElasticSpec(kind).name; }

std::optional<double> ContactDurationS(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                       double impact_speed_mps) {
  // A ball on a rigid plane: the effective mass and radius are the ball's own.
  return dem::ClosedFormContactDurationOf(dem::MakeContactLaw(law), ball.MassKg(), ball.RadiusM(),
                                          impact_speed_mps);
}

dem::ContactLawConfig WithContactDuration(dem::ContactLawConfig law, const dem::Ball& ball,
                                          double impact_speed_mps, double contact_duration_s) {
  const std::string law_name(dem::ToString(law.kind));
  if (!(contact_duration_s > 0) || !std::isfinite(contact_duration_s)) {
    throw OptionError(
        {"contact_duration_s"},
        fmt::format(
            "contact_duration_s must be a positive number of seconds (e.g. 0.005 for a tennis "
            "ball), got {}",
            contact_duration_s));
  }
  const dem::ParameterSpec& spec = ElasticSpec(law.kind);
  const std::string name(spec.name);
  const auto duration_at = [&](double value) {
    law.parameters[name] = value;
    return ContactDurationS(law, ball, impact_speed_mps);
  };
  double value = law.Get(name);
  auto duration = duration_at(value);
  if (!duration) {
    throw OptionError(
        {"contact_duration_s"},
        fmt::format(
            "the {} law has no closed-form contact duration to set {} from contact_duration_s; "
            "give the law's {} instead (`parameters`)",
            law_name, name, name));
  }
  // t_c is a power of the elastic parameter for every law here (k^(-1/2), E*^(-2/5)) up to the
  // damping term of some; Newton's step in log-log space with the measured local exponent
  // converges in a few steps and reaches 1e-12 for the pure powers at once.
  double exponent = -0.5;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double misfit = std::log(contact_duration_s / *duration);
    if (std::fabs(misfit) < 1e-13) break;
    const double next = value * std::exp(misfit / exponent);
    if (!(next >= spec.min_value && next <= spec.max_value)) {
      value = next;  // the range check below names it
      break;
    }
    const auto next_duration = duration_at(next);
    if (!next_duration) break;
    const double slope = std::log(*next_duration / *duration) / std::log(next / value);
    if (std::isfinite(slope) && slope < 0) exponent = slope;
    value = next;
    duration = next_duration;
  }
  if (!(value >= spec.min_value) || !(value <= spec.max_value)) {
    throw OptionError(
        {"contact_duration_s"},
        fmt::format(
            "contact_duration_s {} s needs {} = {:.4g} {} for this ball with the {} law, outside "
            "its range [{:g}, {:g}]; check the duration (seconds, e.g. 0.005) and the ball",
            contact_duration_s, name, value, spec.unit, law_name, spec.min_value, spec.max_value));
  }
  if (!(std::fabs(*duration / contact_duration_s - 1) < 1e-9)) {
    throw OptionError(
        {"contact_duration_s"},
        fmt::format(
            "contact_duration_s {} s: no {} of the {} law gives that duration for this ball "
            "(closest found: {:.4g} {}, lasting {:.4g} s); give the law's {} instead",
            contact_duration_s, name, law_name, value, spec.unit, *duration, name));
  }
  law.parameters[name] = value;
  return law;
}

std::string ContactDurationWarning(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                   std::string_view ball_preset, double impact_speed_mps) {
  if (ball_preset.empty()) return "";
  const BallPreset& preset = FindBallPreset(ball_preset);
  if (!preset.contact_duration_s) return "";
  const dem::ParameterSpec* spec = nullptr;
  for (const auto& candidate : dem::ParameterSpecs(law.kind)) {
    if (candidate.alias == "stiffness-n-per-m" || candidate.alias == "modulus-pa")
      spec = &candidate;
  }
  // A stiffness the user chose is theirs to keep.
  if (spec == nullptr || law.parameters.contains(spec->name)) return "";
  const auto duration = ContactDurationS(law, ball, impact_speed_mps);
  const double typical = *preset.contact_duration_s;
  if (!duration || (*duration > typical / 3 && *duration < typical * 3)) return "";
  return fmt::format(
      "{} = {:.3g} {} (the {} law's default) makes the {} ball's contact last {} at {:.3g} m/s, "
      "against about {} for a real one ({}); give `contact_duration_s={:g}` (or your "
      "measured one) so the card's stiffness, and the time step of every scene built on it, fit "
      "the ball",
      spec->name, law.Get(spec->name), spec->unit, dem::ToString(law.kind), preset.name,
      Duration(*duration), impact_speed_mps, Duration(typical), preset.contact_source, typical);
}

}  // namespace bouncecal::calibrate
