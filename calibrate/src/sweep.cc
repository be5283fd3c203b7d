#include "bouncecal/calibrate/sweep.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

double ParseNumber(const std::string& text, const std::string& list) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw ConfigError("'" + text + "' in the value list '" + list +
                    "' is not a number; write lo:hi:step or a,b,c");
}

}  // namespace

std::vector<double> ParseValueList(const std::string& text) {
  std::vector<double> values;
  if (text.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::stringstream stream(text);
    for (std::string part; std::getline(stream, part, ':');) parts.push_back(part);
    if (parts.size() != 3) {
      throw ConfigError("value range '" + text + "' must be lo:hi:step, e.g. 0.1:0.9:0.2");
    }
    const double lo = ParseNumber(parts[0], text), hi = ParseNumber(parts[1], text),
                 step = ParseNumber(parts[2], text);
    if (!(step > 0) || hi < lo || (hi - lo) / step > 1e4) {
      throw ConfigError("value range '" + text + "' needs lo <= hi and 0 < step, at most 10000 " +
                        "values");
    }
    // Index-based so rounding never drops the last value (0.1 + 4 x 0.2 is 0.9000000000000001).
    const int count = static_cast<int>(std::floor((hi - lo) / step + 0.5));
    for (int i = 0; i <= count; ++i) values.push_back(lo + i * step);
  } else {
    std::stringstream stream(text);
    for (std::string part; std::getline(stream, part, ',');)
      values.push_back(ParseNumber(part, text));
  }
  if (values.empty()) throw ConfigError("empty value list; write lo:hi:step or a,b,c");
  return values;
}

SweepSummary Sweep(const SweepOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.first_n < 1) {
    throw OptionError({"first_n"},
                      "first_n must be at least 1, got " + std::to_string(options.first_n));
  }
  SweepSummary summary;
  for (double value : options.values) {
    dem::DropOptions drop = options.drop;
    drop.law.parameters[options.parameter] = value;
    drop.law.Validate();
    drop.max_impacts = options.first_n + 1;
    const auto result = dem::SimulateDrop(drop);

    SweepPoint point;
    point.value = value;
    point.impacts = static_cast<int>(result.impacts.size());
    point.time_step_s = result.time_step_s;
    if (!result.impacts.empty()) {
      const auto& first = result.impacts.front();
      point.first_contact_energy_loss = 1 - first.restitution * first.restitution;
      point.analytic_energy_loss = ClosedFormEnergyLoss(drop.law, drop.ball, first.speed_in_mps);
      summary.first_impact_speed_mps = first.speed_in_mps;
    }
    // Flight-time energy losses, padded with 1 (all energy lost) if the ball came to rest.
    std::vector<double> energy_loss;
    double incoming = DropFlightTime(drop.drop_height_m, drop.gravity_mps2);
    for (size_t k = 0; k + 1 < result.impacts.size(); ++k) {
      const double outgoing = result.impacts[k + 1].time_s - result.impacts[k].time_s;
      energy_loss.push_back(1 - std::pow(outgoing / incoming, 2));
      incoming = outgoing;
    }
    while (static_cast<int>(energy_loss.size()) < options.first_n) energy_loss.push_back(1.0);
    point.first_energy_loss = energy_loss.front();
    double sum = 0;
    for (int k = 0; k < options.first_n; ++k) sum += energy_loss[static_cast<size_t>(k)];
    point.energy_loss_mean_first_n = sum / options.first_n;
    summary.points.push_back(point);
  }
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

std::optional<double> ClosedFormEnergyLoss(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                           double impact_speed_mps) {
  const auto e = dem::ClosedFormRestitutionOf(dem::MakeContactLaw(law), ball.MassKg(),
                                              ball.RadiusM(), impact_speed_mps);
  if (!e) return std::nullopt;
  return 1 - *e * *e;
}

}  // namespace bouncecal::calibrate
