#include "bouncecal/calibrate/fit.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <thread>

#include "bouncecal/error.h"
#include "fit_problem.h"

namespace bouncecal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;
using internal::ParameterMap;

constexpr double kMaxBirgeRatio = 10;
using internal::SequencePlan;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// SplitMix64 (Steele, Lea & Flood 2014): decorrelated per-replicate seeds from one user seed, so
// a replicate's random numbers do not depend on which thread runs it.
std::uint64_t SplitMix64(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ULL;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
  return value ^ (value >> 31);
}

void ValidateOptions(const FitOptions& options) {
  options.law.Validate();
  if (options.drop_height_m && !(*options.drop_height_m > 0 && *options.drop_height_m < 1e3)) {
    throw ConfigError("drop height must be in (0, 1000) m, got " +
                      std::to_string(*options.drop_height_m));
  }
  if (!(options.gravity_mps2 > 0) || !std::isfinite(options.gravity_mps2)) {
    throw ConfigError("gravity must be a positive number of m/s^2, got " +
                      std::to_string(options.gravity_mps2));
  }
  if (options.first_n < 1) {
    throw ConfigError("--first must be at least 1, got " + std::to_string(options.first_n));
  }
  if (options.max_intervals < 0) {
    throw ConfigError("max_intervals must be >= 0 (0: all), got " +
                      std::to_string(options.max_intervals));
  }
  const auto& u = options.uncertainty;
  if (u.bootstrap_samples < 0 || !(u.confidence_level > 0 && u.confidence_level < 1) ||
      u.threads < 1 || !(u.drop_height_uncertainty_m >= 0)) {
    throw ConfigError(
        "uncertainty options: bootstrap samples >= 0, confidence level in (0, 1), threads >= 1 and "
        "drop-height uncertainty >= 0 m are required");
  }
}

// The search problem over a fixed set of plans: objective evaluation and the minimisation.
class Problem {
 public:
  Problem(const FitOptions& options, const ParameterMap& map, std::vector<SequencePlan> plans)
      : options_(options), map_(map), plans_(std::move(plans)) {}

  double Evaluate(std::span<const double> x) const {
    const auto law = map_.Apply(options_.law, x);
    double chi_square = 0;
    for (const auto& plan : plans_) {
      chi_square += internal::SequenceResidual(
          plan, internal::SimulateSequence(law, plan, options_), options_);
    }
    return chi_square;
  }

  MinimizerSummary Minimize(const MinimizerOptions& minimizer_options,
                            std::vector<double> start) const {
    const BoundedMinimizer minimizer(map_.LowerBounds(), map_.UpperBounds(), minimizer_options);
    return minimizer.Minimize([this](std::span<const double> x) { return Evaluate(x); },
                              std::move(start));
  }

  const std::vector<SequencePlan>& plans() const { return plans_; }

 private:
  const FitOptions& options_;
  const ParameterMap& map_;
  std::vector<SequencePlan> plans_;
};

std::vector<SequencePlan> MakePlans(const std::vector<MeasuredSequence>& sequences,
                                    const FitOptions& options,
                                    std::optional<double> drop_height_m) {
  std::vector<SequencePlan> plans;
  for (const auto& sequence : sequences)
    plans.push_back(internal::MakePlan(sequence, options, drop_height_m));
  return plans;
}

MinimizerOptions MainMinimizerOptions(const FitOptions& options, size_t parameters) {
  MinimizerOptions result = options.minimizer;
  if (result.global_evaluations < 0) {
    const bool unimodal = parameters == 1 && options.objective == FitObjective::kMeanEnergyLoss;
    result.global_evaluations = unimodal ? 0 : 12 * static_cast<int>(parameters);
  }
  result.global_evaluations = std::min(result.global_evaluations, result.max_evaluations - 1);
  return result;
}

double Quantile(std::vector<double> values, double probability) {
  std::sort(values.begin(), values.end());
  const double position = probability * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, values.size() - 1);
  const double fraction = position - static_cast<double>(below);
  return values[below] * (1 - fraction) + values[above] * fraction;
}

// Parametric bootstrap (Efron & Tibshirani 1993, ch. 6): each replicate redraws every onset from
// N(measured, (inflation sigma)^2) and the drop height from N(h0, sigma_h0^2); with several
// recordings it also resamples the recordings with replacement, so their spread enters. Each
// replicate is refitted with the local method from the best fit. The interval is the percentile
// interval of the refitted values.
void Bootstrap(const std::vector<MeasuredSequence>& sequences, const FitOptions& options,
               const ParameterMap& map, const std::vector<double>& best_x, double inflation,
               FitSummary& summary) {
  const int samples = options.uncertainty.bootstrap_samples;
  if (samples == 0) return;
  std::vector<std::vector<double>> replicate_x(static_cast<size_t>(samples));
  std::vector<char> ok(static_cast<size_t>(samples), 0);
  MinimizerOptions local = options.minimizer;
  local.global_evaluations = 0;
  local.parameter_tolerance = std::max(local.parameter_tolerance, 1e-4);
  local.max_evaluations = 60 * static_cast<int>(map.size());
  local.max_time_s = 0;

  std::atomic<int> next{0};
  auto worker = [&] {
    for (int r = next++; r < samples; r = next++) {
      std::mt19937_64 random(SplitMix64(options.uncertainty.seed ^ SplitMix64(r)));
      std::normal_distribution<double> normal(0.0, 1.0);
      std::vector<MeasuredSequence> drawn;
      for (size_t s = 0; s < sequences.size(); ++s) {
        const size_t pick = sequences.size() > 1 ? random() % sequences.size() : s;
        MeasuredSequence copy = sequences[pick];
        for (auto& impact : copy.impacts)
          impact.onset_s += inflation * impact.uncertainty_s * normal(random);
        drawn.push_back(std::move(copy));
      }
      std::optional<double> drop_height = options.drop_height_m;
      if (drop_height)
        *drop_height += options.uncertainty.drop_height_uncertainty_m * normal(random);
      try {
        const Problem problem(options, map, MakePlans(drawn, options, drop_height));
        replicate_x[static_cast<size_t>(r)] = problem.Minimize(local, best_x).x;
        ok[static_cast<size_t>(r)] = 1;
      } catch (const Error&) {
        // A redraw can reorder two close late onsets; such a replicate is counted, not fitted.
      }
    }
  };
  const int threads = std::min(options.uncertainty.threads, samples);
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();

  const double tail = (1 - options.uncertainty.confidence_level) / 2;
  for (size_t i = 0; i < map.size(); ++i) {
    std::vector<double> values;
    for (int r = 0; r < samples; ++r) {
      if (ok[static_cast<size_t>(r)]) values.push_back(map.Value(i, replicate_x[r][i]));
    }
    summary.bootstrap_samples_used = static_cast<int>(values.size());
    if (values.size() < 2) continue;
    auto& parameter = summary.parameters[i];
    parameter.confidence_interval = {Quantile(values, tail), Quantile(values, 1 - tail)};
    const double mean = std::accumulate(values.begin(), values.end(), 0.0) / values.size();
    double variance = 0;
    for (double v : values) variance += (v - mean) * (v - mean);
    parameter.bootstrap_std = std::sqrt(variance / (values.size() - 1));
  }
  summary.bootstrap_failures = samples - summary.bootstrap_samples_used;
  summary.uncertainty_method =
      "parametric bootstrap, " + std::to_string(summary.bootstrap_samples_used) +
      " refits of onsets redrawn from their timing uncertainty" +
      (inflation >= kMaxBirgeRatio
           ? " (scaled by the Birge ratio, capped at 10: the law misfits the data, so the "
             "interval is a lower bound)"
       : inflation > 1 ? " (scaled by the Birge ratio " + std::to_string(inflation) + ")"
                       : std::string()) +
      (sequences.size() > 1 ? " with the recordings resampled" : "") +
      (options.uncertainty.drop_height_uncertainty_m > 0 ? " and the drop height redrawn" : "") +
      "; " +
      std::to_string(static_cast<int>(std::lround(100 * options.uncertainty.confidence_level))) +
      " % percentile interval";
}

AnalyticCheck MakeCheck(const FitOptions& options, const dem::ContactLawConfig& law,
                        const std::vector<SequencePlan>& plans) {
  AnalyticCheck check;
  if (law.kind != dem::ContactLawKind::kWaltonBraun) {
    check.message = "the closed form eta = 2 gamma / (1 + gamma) holds for walton-braun only";
    return check;
  }
  double sum = 0, variance = 0;
  int count = 0;
  for (const auto& plan : plans) {
    if (!plan.measured.energy_loss_mean_first_n) continue;
    sum += *plan.measured.energy_loss_mean_first_n;
    variance += std::pow(*plan.measured.energy_loss_mean_first_n_uncertainty, 2);
    ++count;
  }
  if (count == 0) {
    check.message = "no recording has " + std::to_string(options.first_n) +
                    " energy losses, so eta-bar is unknown";
    return check;
  }
  check.applicable = true;
  const double eta = sum / count;
  check.energy_loss_mean = eta;
  check.energy_loss_mean_uncertainty = std::sqrt(variance) / count;
  check.gamma_n_formula = eta / (2 - eta);
  const double gamma = law.Get("gamma_n");
  check.gamma_n_fitted = gamma;
  check.difference = gamma - check.gamma_n_formula;

  const SequencePlan& reference = plans.front();
  const auto chosen = internal::SimulateSequence(law, reference, options);
  check.energy_loss_mean_chosen_step = internal::MeanOfFirst(chosen.energy_loss, options.first_n);
  check.energy_loss_formula = 2 * gamma / (1 + gamma);
  const double slope = 2 / std::pow(1 + gamma, 2);  // d eta / d gamma of the closed form
  try {
    const auto exact = internal::SimulateSequence(law, reference, options, dem::Integrator::kExact);
    check.energy_loss_mean_exact = internal::MeanOfFirst(exact.energy_loss, options.first_n);
  } catch (const ConfigError&) {
    check.energy_loss_mean_exact = check.energy_loss_mean_chosen_step;  // no exact path
  }
  check.time_step_gamma_error =
      (check.energy_loss_mean_chosen_step - check.energy_loss_mean_exact) / slope;
  check.model_gamma_error = (check.energy_loss_mean_exact - check.energy_loss_formula) / slope;
  const double formula_sigma = check.energy_loss_mean_uncertainty * 2 / std::pow(2 - eta, 2);
  check.explained = std::abs(check.time_step_gamma_error) + std::abs(check.model_gamma_error) +
                    2 * formula_sigma + 1e-4;  // + the optimiser's tolerance on gamma
  check.warning = std::abs(check.difference) > check.explained;
  char text[400];
  std::snprintf(
      text, sizeof text,
      check.warning ? "fitted gamma_n differs from the formula by %.4f, more than the %.4f that "
                      "time-step error (%.4f), the formula's neglect of gravity during contact "
                      "(%.4f) and timing noise explain: one constant gamma does not describe these "
                      "impacts (try --compare-laws or --objective mean-energy-loss)"
                    : "fitted gamma_n differs from the formula by %.4f, within the %.4f that "
                      "time-step error (%.4f), the formula's neglect of gravity during contact "
                      "(%.4f) and timing noise explain",
      check.difference, check.explained, check.time_step_gamma_error, check.model_gamma_error);
  check.message = text;
  return check;
}

}  // namespace

std::string_view ToString(FitObjective objective) {
  switch (objective) {
    case FitObjective::kMeanEnergyLoss:
      return "mean-energy-loss";
    case FitObjective::kIntervals:
      return "intervals";
    case FitObjective::kHeights:
      return "heights";
  }
  return "unknown";
}

FitObjective FitObjectiveFromString(std::string_view name) {
  for (auto objective :
       {FitObjective::kMeanEnergyLoss, FitObjective::kIntervals, FitObjective::kHeights}) {
    if (name == ToString(objective)) return objective;
  }
  throw ConfigError("unknown objective '" + std::string(name) +
                    "'; use one of mean-energy-loss, intervals, heights");
}

std::vector<std::string> DefaultFittedParameters(dem::ContactLawKind kind) {
  std::vector<std::string> names;
  for (const auto& spec : dem::ParameterSpecs(kind)) {
    if (spec.name == "stiffness_n_per_m" || spec.name == "effective_modulus_pa") continue;
    // Luding's speed-dependent plastic variant is opt-in (--fit plastic_flow_overlap_m): its
    // default 0 is the 1986 form, and a second parameter needs a sequence with many impacts.
    if (spec.name == "plastic_flow_overlap_m") continue;
    names.emplace_back(spec.name);
  }
  return names;
}

ParameterRange DefaultParameterRange(const dem::ContactLawConfig& config, std::string_view name) {
  const dem::ParameterSpec* spec = nullptr;
  for (const auto& candidate : dem::ParameterSpecs(config.kind)) {
    if (candidate.name == name) spec = &candidate;
  }
  if (spec == nullptr) {
    throw ConfigError("law " + std::string(dem::ToString(config.kind)) + " has no parameter '" +
                      std::string(name) + "' to fit");
  }
  // gamma_n = 1 never releases the ball (zero unloading stiffness), and near it the drop engine
  // spends its whole time budget; 0.98 already means eta = 0.99.
  if (name == "gamma_n") return {0.0, 0.98, false};
  // zeta -> 1 is critical damping, which never releases the ball either.
  if (name == "damping_ratio") return {0.0, 0.95, false};
  // e = sqrt(k1/k2): [k1, 1e4 k1] covers e from 1 down to 0.01.
  if (name == "unloading_stiffness_n_per_m") {
    const double k1 = config.Get("stiffness_n_per_m");
    return {k1 * (1 + 1e-9), k1 * 1e4, true};
  }
  // Luding's flow overlap: impact overlaps of mm-to-cm balls are 1e-6 to 1e-4 m; 0 is the
  // 1986 form, so the range is linear and includes it.
  if (name == "plastic_flow_overlap_m") return {0.0, 1e-3, false};
  // Brilliantov's dissipative time: 1 ns (nearly elastic) to 0.1 ms (e ~ 0 for mm-sized balls).
  if (name == "dissipative_time_s") return {1e-9, 1e-4, true};
  ParameterRange range{spec->min_value, spec->max_value, false};
  if (!std::isfinite(range.upper)) range.upper = std::max(1.0, spec->default_value) * 1e3;
  if (range.lower > 0 && range.upper / range.lower >= 100) range.log_scale = true;
  return range;
}

FitSummary Fit(const std::vector<MeasuredSequence>& sequences, const FitOptions& options) {
  const auto start = Clock::now();
  ValidateOptions(options);
  if (sequences.empty()) throw ConfigError("no recording to fit; give at least one");
  const ParameterMap map(options);
  const Problem problem(options, map, MakePlans(sequences, options, options.drop_height_m));

  FitSummary summary;
  summary.objective = options.objective;
  const auto minimized =
      problem.Minimize(MainMinimizerOptions(options, map.size()), map.StartPoint(options.law));
  summary.fit_time_s = SecondsSince(start);
  summary.stop = minimized.stop;
  summary.stop_message = minimized.message;
  summary.evaluations = minimized.evaluations;
  summary.residual = minimized.value;
  summary.law = map.Apply(options.law, minimized.x);

  for (size_t i = 0; i < map.size(); ++i) {
    FittedParameter parameter;
    parameter.name = map.names()[i];
    for (const auto& spec : dem::ParameterSpecs(options.law.kind)) {
      if (spec.name == parameter.name) parameter.unit = spec.unit;
    }
    parameter.range = map.ranges()[i];
    parameter.value = map.Value(i, minimized.x[i]);
    const double width = map.UpperBounds()[i] - map.LowerBounds()[i];
    parameter.at_bound = std::min(minimized.x[i] - map.LowerBounds()[i],
                                  map.UpperBounds()[i] - minimized.x[i]) < 1e-3 * width;
    summary.parameters.push_back(parameter);
  }

  for (const auto& plan : problem.plans()) {
    SequenceFit fit;
    fit.source = plan.source;
    fit.measured = plan.measured;
    int points = 0;
    fit.residual = internal::SequenceResidual(
        plan, internal::SimulateSequence(summary.law, plan, options), options, &points);
    // For the report, the fitted drop runs over the whole measured sequence, whatever the
    // objective compared.
    SequencePlan whole = plan;
    whole.impacts_needed = static_cast<int>(plan.impacts.size()) - plan.first_matched_impact;
    const auto simulated = internal::SimulateSequence(summary.law, whole, options);
    summary.data_points += points;
    // Onto the measured time axis: the first simulated impact at the measured impact it stands for.
    const double shift = plan.impacts[static_cast<size_t>(plan.first_matched_impact)].onset_s -
                         (simulated.onsets_s.empty() ? 0.0 : simulated.onsets_s.front());
    for (double onset : simulated.onsets_s) fit.simulated_onsets_s.push_back(onset + shift);
    RestitutionOptions restitution;
    restitution.gravity_mps2 = options.gravity_mps2;
    restitution.first_n = options.first_n;
    restitution.drop_height_m = plan.release_height_m;
    if (fit.simulated_onsets_s.size() >= 2) {
      std::vector<TimedImpact> timed;
      for (double onset : simulated.onsets_s) timed.push_back({onset, 0.0});
      fit.simulated = AnalyzeRestitution(timed, restitution);
    }
    if (&plan == &problem.plans().front()) {
      summary.implied_restitution = simulated.first_restitution;
      summary.implied_energy_loss = 1 - simulated.first_restitution * simulated.first_restitution;
    }
    summary.sequences.push_back(std::move(fit));
  }
  const int k = static_cast<int>(map.size());
  summary.degrees_of_freedom = summary.data_points - k;
  summary.reduced_chi_square =
      summary.degrees_of_freedom > 0 ? summary.residual / summary.degrees_of_freedom : 0;
  summary.aic = summary.residual + 2.0 * k;
  summary.bic = summary.residual + k * std::log(std::max(summary.data_points, 1));

  if (options.analytic_check) summary.check = MakeCheck(options, summary.law, problem.plans());
  // Birge ratio: when the misfit exceeds what the stated timing noise explains, the noise (or the
  // model) is worse than stated; scaling the redraws keeps the interval honest.
  // Capped at 10: beyond that the law does not describe the data (see CompareLaws) and redraws
  // that large would reorder the late onsets; the interval is then a lower bound, and says so.
  const double birge = summary.reduced_chi_square > 1 ? std::sqrt(summary.reduced_chi_square) : 1.0;
  const double inflation = std::min(birge, kMaxBirgeRatio);
  summary.uncertainty_method = "none (bootstrap samples = 0)";
  Bootstrap(sequences, options, map, minimized.x, inflation, summary);
  summary.total_time_s = SecondsSince(start);
  return summary;
}

LawComparison CompareLaws(const std::vector<MeasuredSequence>& sequences,
                          const std::vector<dem::ContactLawKind>& laws, const FitOptions& options) {
  std::vector<dem::ContactLawKind> fittable;
  for (auto kind : laws) {
    if (!DefaultFittedParameters(kind).empty()) fittable.push_back(kind);
  }
  if (fittable.empty()) throw ConfigError("none of the laws to compare has a damping parameter");
  std::vector<FitSummary> fits(fittable.size());
  std::vector<std::exception_ptr> errors(fittable.size());
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i = next++; i < fittable.size(); i = next++) {
      try {
        FitOptions law_options = options;
        law_options.law = {fittable[i], {}};
        // Keep the parameters this law shares by name (stiffness_n_per_m for the linear laws).
        for (const auto& spec : dem::ParameterSpecs(fittable[i])) {
          if (auto it = options.law.parameters.find(spec.name); it != options.law.parameters.end())
            law_options.law.parameters[it->first] = it->second;
        }
        law_options.fitted_parameters.clear();
        law_options.ranges.clear();
        law_options.uncertainty.threads = 1;  // the laws already share the threads
        fits[i] = Fit(sequences, law_options);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const int threads = std::min<int>(options.uncertainty.threads, static_cast<int>(fittable.size()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  std::stable_sort(fits.begin(), fits.end(),
                   [](const FitSummary& a, const FitSummary& b) { return a.bic < b.bic; });
  return {std::move(fits)};
}

}  // namespace bouncecal::calibrate
