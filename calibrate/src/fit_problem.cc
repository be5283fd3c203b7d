#include "fit_problem.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "bouncecal/calibrate/drop_height_check.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate::internal {
namespace {

// Interval sigmas below this (an uncertainty of 0 in a hand-written CSV) would make the weights
// infinite; 0.1 us is far below any audio timing (one sample at 192 kHz is 5 us).
constexpr double kMinSigmaS = 1e-7;

}  // namespace

OptionError TooFewEnergyLosses(const SequencePlan& plan, int available, int first_n) {
  // With the height given, only more audible impacts or a smaller first_n help.
  const std::string more = plan.known_drop_height
                               ? std::string("use a recording with more audible impacts")
                               : std::string("give drop_height_m");
  const std::string fix =
      available == 0 ? more : "set first_n to " + std::to_string(available) + " or " + more;
  return OptionError({"first_n", "drop_height_m"},
                     "recording " + plan.source + " gives " + std::to_string(available) +
                         " energy losses but first_n " + std::to_string(first_n) +
                         " needs that many; " + fix);
}

SequencePlan MakePlan(const MeasuredSequence& sequence, const FitOptions& options,
                      std::optional<double> drop_height_m) {
  SequencePlan plan;
  plan.source = sequence.source;
  plan.path = sequence.path;
  plan.impacts = sequence.impacts;
  RestitutionOptions restitution;
  restitution.gravity_mps2 = options.drop.gravity_mps2;
  restitution.first_n = options.first_n;
  restitution.drop_height_m = drop_height_m;
  plan.measured = AnalyzeRestitution(sequence.impacts, restitution);
  if (plan.measured.intervals_s.empty()) {
    throw ConfigError("recording " + sequence.source + " has fewer than two impacts; a fit needs " +
                      "at least one flight interval");
  }
  plan.known_drop_height = drop_height_m.has_value();
  if (plan.known_drop_height) {
    RefuseReboundAboveRelease(sequence.source, plan.measured, *drop_height_m);
    // A height the later bounces contradict would be fitted as a first impact that lost far more
    // energy than the rest: refused, with the height the bounces imply.
    const auto check = CheckDropHeight(plan.measured, *drop_height_m, options.drop.gravity_mps2);
    if (check && !check->consistent) {
      throw OptionError({"drop_height_m"}, DescribeInconsistentDropHeight(sequence.source, *check));
    }
    plan.release_height_m = *drop_height_m;
    plan.first_matched_impact = 0;
  } else {
    // The apex of the first measured flight is a release from rest for the rest of the sequence.
    const double first = plan.measured.intervals_s.front();
    plan.release_height_m = options.drop.gravity_mps2 * first * first / 8.0;
    plan.first_matched_impact = 1;
  }
  const int measured_impacts = static_cast<int>(sequence.impacts.size());
  int intervals = measured_impacts - 1 - plan.first_matched_impact;
  if (options.max_intervals > 0) intervals = std::min(intervals, options.max_intervals);
  if (options.objective == FitObjective::kMeanEnergyLoss) {
    const auto available = static_cast<int>(plan.measured.energy_loss.size());
    if (available < options.first_n && (options.first_n_given || available == 0)) {
      throw TooFewEnergyLosses(plan, available, options.first_n);
    }
    plan.first_n = std::min(options.first_n, available);
    if (plan.first_n < options.first_n) {
      restitution.first_n = plan.first_n;
      plan.measured = AnalyzeRestitution(sequence.impacts, restitution);
    }
    plan.impacts_needed = plan.first_n + 1;
  } else {
    if (intervals < 1) {
      throw ConfigError("recording " + sequence.source + " has no flight interval to fit after " +
                        "the first one; give the drop height or use a longer recording");
    }
    plan.impacts_needed = intervals + 1;
  }
  // Simulated time: the measured span it compares plus the first fall, with 50 % headroom for
  // parameters that bounce longer than the measurement.
  const double span = sequence.impacts.back().onset_s - sequence.impacts.front().onset_s;
  plan.max_time_s =
      1.5 * span + 2.0 * std::sqrt(2.0 * plan.release_height_m / options.drop.gravity_mps2);
  return plan;
}

double IncomingSpeedMps(const SequencePlan& plan, int impact, double gravity_mps2) {
  if (impact == 0) return std::sqrt(2 * gravity_mps2 * plan.release_height_m);
  return gravity_mps2 * plan.measured.intervals_s[static_cast<size_t>(impact - 1)] / 2;
}

ParameterMap::ParameterMap(const FitOptions& options) {
  names_ = options.fitted_parameters.empty() ? DefaultFittedParameters(options.drop.law.kind)
                                             : options.fitted_parameters;
  if (names_.empty()) {
    throw ConfigError("law " + std::string(dem::ToString(options.drop.law.kind)) +
                      " has no dissipative parameter to fit; choose a damped law");
  }
  for (const auto& name : names_) {
    ParameterRange range = DefaultParameterRange(options.drop.law, name);
    if (auto it = options.ranges.find(name); it != options.ranges.end()) range = it->second;
    if (!(range.lower < range.upper) || !std::isfinite(range.lower) ||
        !std::isfinite(range.upper) || (range.log_scale && !(range.lower > 0))) {
      throw ConfigError("search range of " + name + " must be finite with lower < upper (and " +
                        "lower > 0 in log scale), got [" + std::to_string(range.lower) + ", " +
                        std::to_string(range.upper) + "]");
    }
    ranges_.push_back(range);
  }
}

std::vector<double> ParameterMap::LowerBounds() const {
  std::vector<double> bounds;
  for (const auto& range : ranges_)
    bounds.push_back(range.log_scale ? std::log(range.lower) : range.lower);
  return bounds;
}

std::vector<double> ParameterMap::UpperBounds() const {
  std::vector<double> bounds;
  for (const auto& range : ranges_)
    bounds.push_back(range.log_scale ? std::log(range.upper) : range.upper);
  return bounds;
}

std::vector<double> ParameterMap::StartPoint(const dem::ContactLawConfig& law) const {
  std::vector<double> x;
  for (size_t i = 0; i < names_.size(); ++i) {
    const double value = std::clamp(law.Get(names_[i]), ranges_[i].lower, ranges_[i].upper);
    x.push_back(ranges_[i].log_scale ? std::log(value) : value);
  }
  return x;
}

double ParameterMap::Value(size_t i, double x) const {
  const double value = ranges_[i].log_scale ? std::exp(x) : x;
  return std::clamp(value, ranges_[i].lower, ranges_[i].upper);
}

dem::ContactLawConfig ParameterMap::Apply(const dem::ContactLawConfig& law,
                                          std::span<const double> x) const {
  dem::ContactLawConfig result = law;
  for (size_t i = 0; i < names_.size(); ++i) result.parameters[names_[i]] = Value(i, x[i]);
  return result;
}

double MeanOfFirst(const std::vector<double>& energy_loss, int n) {
  double sum = 0;
  for (int j = 0; j < n; ++j)
    sum += j < static_cast<int>(energy_loss.size()) ? energy_loss[j] : 1.0;
  return sum / n;
}

SimulatedSequence SimulateSequence(const dem::ContactLawConfig& law, const SequencePlan& plan,
                                   const FitOptions& options,
                                   std::optional<dem::Integrator> integrator_override) {
  dem::DropOptions drop = options.drop;
  drop.law = law;
  drop.drop_height_m = plan.release_height_m;
  if (integrator_override) drop.integrator = *integrator_override;
  drop.max_impacts = plan.impacts_needed;
  drop.max_time_s = plan.max_time_s;
  drop.trajectory_interval_s = 0;  // only the impacts are compared
  const dem::DropResult result = dem::SimulateDrop(drop);

  SimulatedSequence simulated;
  for (const auto& impact : result.impacts) simulated.onsets_s.push_back(impact.time_s);
  if (!result.impacts.empty()) simulated.first_restitution = result.impacts.front().restitution;
  for (size_t j = 0; j + 1 < simulated.onsets_s.size(); ++j)
    simulated.intervals_s.push_back(simulated.onsets_s[j + 1] - simulated.onsets_s[j]);
  // The same estimator as the measurement (flight ratios, dt_0 from the release height), so
  // contact duration and gravity during contact bias both sides alike.
  double incoming = DropFlightTime(plan.release_height_m, options.drop.gravity_mps2);
  for (double outgoing : simulated.intervals_s) {
    const double e = outgoing / incoming;
    simulated.energy_loss.push_back(1.0 - e * e);
    incoming = outgoing;
  }
  return simulated;
}

ObjectiveTerms Terms(const SequencePlan& plan, const SimulatedSequence& simulated,
                     const FitOptions& options) {
  const auto& measured = plan.measured;
  ObjectiveTerms terms;
  if (options.objective == FitObjective::kMeanEnergyLoss) {
    terms.model.push_back(MeanOfFirst(simulated.energy_loss, plan.first_n));
    terms.data.push_back(*measured.energy_loss_mean_first_n);
    const double timing =
        std::max(*measured.energy_loss_mean_first_n_uncertainty, kMinSigmaS);  // dimensionless
    terms.sigma.push_back(std::sqrt(timing * timing + plan.extra_variance));
    return terms;
  }
  const int count = plan.impacts_needed - 1;
  const double g = options.drop.gravity_mps2;
  for (int j = 0; j < count; ++j) {
    const size_t m = static_cast<size_t>(plan.first_matched_impact + j);
    const double measured_interval = measured.intervals_s[m];
    const double sigma = std::max(measured.interval_uncertainty_s[m], kMinSigmaS);
    // A ball that came to rest early has flights of zero length left.
    const double simulated_interval =
        j < static_cast<int>(simulated.intervals_s.size()) ? simulated.intervals_s[j] : 0.0;
    if (options.objective == FitObjective::kIntervals) {
      terms.model.push_back(simulated_interval);
      terms.data.push_back(measured_interval);
      terms.sigma.push_back(sigma);
    } else {
      terms.model.push_back(g * simulated_interval * simulated_interval / 8.0);
      terms.data.push_back(g * measured_interval * measured_interval / 8.0);
      terms.sigma.push_back(std::max(g * measured_interval * sigma / 4.0, 1e-12));
    }
  }
  return terms;
}

double SequenceResidual(const SequencePlan& plan, const SimulatedSequence& simulated,
                        const FitOptions& options, int* data_points) {
  const auto terms = Terms(plan, simulated, options);
  double chi_square = 0;
  for (size_t i = 0; i < terms.model.size(); ++i) {
    const double residual = (terms.model[i] - terms.data[i]) / terms.sigma[i];
    chi_square += residual * residual;
  }
  if (data_points) *data_points = static_cast<int>(terms.model.size());
  return chi_square;
}

std::vector<size_t> UsedEnergyLossEntries(const SequencePlan& plan) {
  std::vector<size_t> used;
  const int first = plan.first_matched_impact;
  const int last = plan.first_matched_impact + plan.impacts_needed - 2;
  for (size_t j = 0; j < plan.measured.impact_index.size(); ++j) {
    const int impact = plan.measured.impact_index[j];
    if (impact >= first && impact <= last) used.push_back(j);
  }
  return used;
}

}  // namespace bouncecal::calibrate::internal
