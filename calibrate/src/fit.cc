#include "bouncecal/calibrate/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>

#include "analytic_check.h"
#include "bouncecal/calibrate/contact_stiffness.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "bouncecal/worker_pool.h"
#include "fit_problem.h"
#include "fit_uncertainty.h"
#include "model_adequacy.h"
#include "student_t.h"

namespace bouncecal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;
using internal::ParameterMap;

using internal::SequencePlan;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

bool SameBall(const dem::Ball& a, const dem::Ball& b) {
  return a.diameter_m == b.diameter_m && a.density_kg_per_m3 == b.density_kg_per_m3 &&
         a.mass_kg == b.mass_kg;
}

void ValidateOptions(const FitOptions& options) {
  const dem::DropOptions& drop = options.drop;
  drop.law.Validate();
  // A value set without its flag would otherwise be silently replaced by the reference ball or
  // by the first bounce's apex.
  if (!options.ball_given && !SameBall(drop.ball, ReferenceBall())) {
    throw ConfigError(
        "FitOptions: drop.ball is set but ball_given is false; set ball_given = true for the "
        "experiment's ball, or leave drop.ball at ReferenceBall()");
  }
  if (!options.first_n_given && options.first_n != FitOptions{}.first_n) {
    throw ConfigError(
        "FitOptions: first_n is set but first_n_given is false; set first_n_given = true for the "
        "impacts to average, or leave first_n at its default");
  }
  if (!options.drop_height_given && drop.drop_height_m != dem::DropOptions{}.drop_height_m) {
    throw ConfigError(
        "FitOptions: drop.drop_height_m is set but drop_height_given is false; set "
        "drop_height_given = true for the release height, or leave drop.drop_height_m at its "
        "default");
  }
  options.ValidateSettings();
  if (options.ball_given) {
    drop.ball.Validate();
  } else if (const auto why = WhyResultDependsOnBall(options); !why.empty()) {
    throw OptionError(
        {"ball", "diameter_m", "density_kg_per_m3", "mass_kg"},
        "the ball is needed: with " + why +
            " the fitted damping depends on its size and mass; give `ball` NAME (e.g. "
            "steel-10mm, pingpong-40mm, tennis) or diameter_m with "
            "density_kg_per_m3 or mass_kg");
  }
}

// Sequences with identical impact times are one recording given twice (the same file, a copy,
// or the analyze --json of it): fitting both would count one measurement as two and shrink the
// interval. The first is kept.
std::vector<MeasuredSequence> DistinctSequences(const std::vector<MeasuredSequence>& sequences,
                                                std::vector<std::string>& warnings,
                                                int& duplicates) {
  std::vector<MeasuredSequence> distinct;
  for (const auto& sequence : sequences) {
    const MeasuredSequence* original = nullptr;
    for (const auto& kept : distinct) {
      const bool same =
          kept.impacts.size() == sequence.impacts.size() &&
          std::equal(kept.impacts.begin(), kept.impacts.end(), sequence.impacts.begin(),
                     [](const TimedImpact& a, const TimedImpact& b) {
                       return a.onset_s == b.onset_s && a.uncertainty_s == b.uncertainty_s &&
                              a.incoming_flight_uncertainty_s == b.incoming_flight_uncertainty_s;
                     });
      if (same) original = &kept;
    }
    if (original == nullptr) {
      distinct.push_back(sequence);
      continue;
    }
    ++duplicates;
    const bool same_file =
        !sequence.content_hash.empty() && sequence.content_hash == original->content_hash;
    warnings.push_back(sequence.source + " has the same impact times as " + original->source +
                       (same_file ? " (same file content, " + sequence.content_hash + ")" : "") +
                       ", so it is counted once; give a separate recording of another drop to "
                       "narrow the interval");
  }
  return distinct;
}

// The search problem over a fixed set of plans: objective evaluation and the minimisation.
class Problem {
 public:
  Problem(const FitOptions& options, const ParameterMap& map, std::vector<SequencePlan> plans)
      : options_(options), map_(map), plans_(std::move(plans)) {}

  double Evaluate(std::span<const double> x) const {
    const auto law = map_.Apply(options_.drop.law, x);
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

// Each sequence is released from its own height when it has one, else from the fit's. The fit's
// height is one measurement shared by its sequences (group 0); a sequence's own height is its
// recording's measurement (one group per recording file).
std::vector<SequencePlan> MakePlans(const std::vector<MeasuredSequence>& sequences,
                                    const FitOptions& options) {
  std::vector<SequencePlan> plans;
  std::vector<std::filesystem::path> own_height_files;
  for (const auto& sequence : sequences) {
    const auto height =
        sequence.drop_height_m ? sequence.drop_height_m : options.GivenDropHeightM();
    auto plan = internal::MakePlan(sequence, options, height);
    if (sequence.drop_height_m) {
      plan.drop_height_uncertainty_m = sequence.drop_height_uncertainty_m;
      const auto file = std::find(own_height_files.begin(), own_height_files.end(), sequence.path);
      plan.drop_height_group = 1 + static_cast<int>(file - own_height_files.begin());
      if (file == own_height_files.end()) own_height_files.push_back(sequence.path);
    } else if (height) {
      plan.drop_height_uncertainty_m = options.uncertainty.drop_height_uncertainty_m;
    }
    plans.push_back(std::move(plan));
  }
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

// The trend test over the residuals of every measured impact about the fitted law.
ModelAdequacy TestAdequacy(const FitOptions& options, const dem::ContactLawConfig& law,
                           const std::vector<SequencePlan>& plans, bool comparing) {
  internal::AdequacyContext context;
  context.law = std::string(dem::ToString(options.drop.law.kind));
  FitOptions without_drag = options;
  without_drag.drop.drag.enabled = false;
  context.speed_dependent = ResultDependsOnBall(without_drag);
  context.comparing = comparing;
  return internal::TestSpeedTrend(internal::EveryImpactResiduals(plans, options, law), context);
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
    if (spec.role == dem::ParameterRole::kDissipative) names.emplace_back(spec.name);
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
  const dem::FitRange& fit = spec->fit;
  const double scale = fit.relative_to.empty() ? 1.0 : config.Get(fit.relative_to);
  return {fit.lower * scale, fit.upper * scale, fit.log_scale};
}

dem::Ball ReferenceBall() {
  dem::Ball ball;
  ball.diameter_m = 0.01;
  ball.density_kg_per_m3 = 7800;
  return ball;
}

std::optional<dem::Ball> FitOptions::GivenBall() const {
  if (!ball_given) return std::nullopt;
  return drop.ball;
}

void FitOptions::ValidateSettings() const {
  if (drop_height_given && !(drop.drop_height_m > 0 && drop.drop_height_m < 1e3)) {
    throw OptionError({"drop_height_m"}, "drop_height_m must be in (0, 1000) m, got " +
                                             std::to_string(drop.drop_height_m));
  }
  if (!(drop.gravity_mps2 > 0) || !std::isfinite(drop.gravity_mps2)) {
    throw OptionError({"gravity_mps2"}, "gravity_mps2 must be a positive number of m/s^2, got " +
                                            std::to_string(drop.gravity_mps2));
  }
  if (first_n < 1) {
    throw OptionError({"first_n"}, "first_n must be at least 1, got " + std::to_string(first_n));
  }
  if (max_intervals < 0) {
    throw OptionError({"max_intervals"},
                      "max_intervals must be >= 0 (0: all), got " + std::to_string(max_intervals));
  }
  if (minimizer.max_evaluations < 1) {
    throw OptionError({"max_evaluations"}, "max_evaluations must be >= 1, got " +
                                               std::to_string(minimizer.max_evaluations));
  }
  const auto& u = uncertainty;
  if (!(u.confidence_level > 0 && u.confidence_level < 1)) {
    throw OptionError({"confidence_level"}, "confidence_level must be in (0, 1), e.g. 0.95, got " +
                                                std::to_string(u.confidence_level));
  }
  if (u.threads < 1) {
    throw OptionError({"threads"}, "`threads` must be >= 1, got " + std::to_string(u.threads));
  }
  if (!(u.drop_height_uncertainty_m >= 0 && std::isfinite(u.drop_height_uncertainty_m))) {
    throw OptionError({"drop_height_uncertainty_m"},
                      "drop_height_uncertainty_m must be >= 0 m, got " +
                          std::to_string(u.drop_height_uncertainty_m));
  }
  if (u.drop_height_uncertainty_m > 0 && !drop_height_given) {
    throw OptionError({"drop_height_uncertainty_m", "drop_height_m"},
                      "drop_height_uncertainty_m needs drop_height_m (without a height nothing "
                      "depends on it)");
  }
}

std::optional<double> FitOptions::GivenDropHeightM() const {
  if (!drop_height_given) return std::nullopt;
  return drop.drop_height_m;
}

std::string WhyResultDependsOnBall(const FitOptions& options) {
  if (options.drop.drag.enabled) return "air drag";
  const auto kind = options.drop.law.kind;
  const std::string law(dem::ToString(kind));
  const auto& fitted = options.fitted_parameters;
  for (const auto& spec : dem::ParameterSpecs(kind)) {
    if (spec.ball_dependence == dem::BallDependence::kAlways) return "the " + law + " law";
    const bool used = std::find(fitted.begin(), fitted.end(), spec.name) != fitted.end() ||
                      options.drop.law.Get(spec.name) != 0;
    if (spec.ball_dependence == dem::BallDependence::kWhenUsed && used)
      return "the " + law + " law's " + std::string(spec.name);
  }
  return "";
}

bool ResultDependsOnBall(const FitOptions& options) {
  return !WhyResultDependsOnBall(options).empty();
}

namespace {

// FitOptions::first_n_given: MakePlan let each recording that gives fewer energy losses than the
// default first_n average all it gives. One loss is enough only beside a recording that shows the
// impacts' scatter (kFewestDefaultFirstN); the warning names the recordings that averaged fewer.
void CheckFewerEnergyLosses(const std::vector<internal::SequencePlan>& plans,
                            const FitOptions& options, std::vector<std::string>& warnings) {
  if (options.objective != FitObjective::kMeanEnergyLoss) return;
  int most = 0;
  int fewest = options.first_n;
  int shorter = 0;
  std::string names;
  for (const auto& plan : plans) {
    most = std::max(most, plan.first_n);
    fewest = std::min(fewest, plan.first_n);
    if (plan.first_n == options.first_n) continue;
    names += (shorter++ > 0 ? ", " : "") + plan.source + " gives " + std::to_string(plan.first_n);
  }
  if (shorter == 0) return;
  if (most < kFewestDefaultFirstN) {
    throw internal::TooFewEnergyLosses(plans.front(), plans.front().first_n, options.first_n);
  }
  warnings.push_back(
      std::string(shorter > 1 ? "recordings " : "recording ") + names +
      " energy losses, fewer than the " + std::to_string(options.first_n) +
      " eta-bar averages by default, so " + (shorter > 1 ? "each of their" : "its") +
      " eta-bar averages all it gives (the impacts' scatter is then known less well and the "
      "interval is wider); record more audible bounces" +
      // One loss in every recording would leave the scatter to the spread between recordings.
      (fewest >= kFewestDefaultFirstN
           ? ", or give `first_n=" + std::to_string(fewest) + "` for that many in every recording"
           : std::string()));
}

FitSummary FitSequences(const std::vector<MeasuredSequence>& input, const FitOptions& options,
                        bool comparing) {
  const auto start = Clock::now();
  ValidateOptions(options);
  if (input.empty()) throw ConfigError("no recording to fit; give at least one");
  FitSummary summary;
  summary.ball_given = options.ball_given;
  summary.objective = options.objective;
  const auto sequences = DistinctSequences(input, summary.warnings, summary.uncertainty.duplicates);
  summary.first_n = options.first_n;
  const ParameterMap map(options);
  const auto plans = MakePlans(sequences, options);
  CheckFewerEnergyLosses(plans, options, summary.warnings);
  const Problem problem(options, map, plans);

  auto minimized =
      problem.Minimize(MainMinimizerOptions(options, map.size()), map.StartPoint(options.drop.law));
  // Timing noise alone would weight the recordings of a joint mean-energy-loss fit by how clean
  // their onsets are, whereas their eta-bar differ by the impacts' own scatter: refit once with
  // each recording's eta-bar variance including the per-impact scatter (and the between-recording
  // spread) found at the first fit. Intervals and heights keep their timing weights (their
  // interval accounts for the scatter all the same).
  std::vector<SequencePlan> weighted = plans;
  if (options.objective == FitObjective::kMeanEnergyLoss && plans.size() >= 2) {
    const auto scatter = internal::ScatterAt(plans, options, map, minimized.x);
    for (auto& plan : weighted) {
      plan.extra_variance = scatter.within_variance / plan.first_n + scatter.between_variance;
    }
    MinimizerOptions local = options.minimizer;
    local.global_evaluations = 0;
    const Problem reweighted(options, map, weighted);
    const int first_evaluations = minimized.evaluations;
    minimized = reweighted.Minimize(local, minimized.x);
    minimized.evaluations += first_evaluations;
  }
  summary.fit_time_s = SecondsSince(start);
  summary.stop = minimized.stop;
  summary.stop_message = minimized.message;
  summary.evaluations = minimized.evaluations;
  summary.residual = problem.Evaluate(minimized.x);  // timing-weighted, whatever the pass
  summary.law = map.Apply(options.drop.law, minimized.x);

  for (size_t i = 0; i < map.size(); ++i) {
    FittedParameter parameter;
    parameter.name = map.names()[i];
    for (const auto& spec : dem::ParameterSpecs(options.drop.law.kind)) {
      if (spec.name == parameter.name) parameter.unit = spec.unit;
    }
    parameter.range = map.ranges()[i];
    parameter.value = map.Value(i, minimized.x[i]);
    const double width = map.UpperBounds()[i] - map.LowerBounds()[i];
    parameter.at_bound = std::min(minimized.x[i] - map.LowerBounds()[i],
                                  map.UpperBounds()[i] - minimized.x[i]) < 1e-3 * width;
    summary.parameters.push_back(parameter);
  }

  for (const auto& plan : plans) {
    SequenceFit fit;
    fit.source = plan.source;
    fit.path = plan.path;
    if (plan.known_drop_height) fit.drop_height_m = plan.release_height_m;
    fit.measured = plan.measured;
    fit.first_n = plan.first_n;
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
    restitution.gravity_mps2 = options.drop.gravity_mps2;
    restitution.first_n = internal::EtaBarCount(plan, options);
    restitution.drop_height_m = plan.release_height_m;
    if (fit.simulated_onsets_s.size() >= 2) {
      std::vector<TimedImpact> timed;
      for (double onset : simulated.onsets_s) timed.push_back({onset, 0.0});
      fit.simulated = AnalyzeRestitution(timed, restitution);
      // Numbered as the measured impacts, so that measured and simulated entries of one impact
      // share an index: the simulation's first impact stands for measured impact
      // first_matched_impact (1 when it starts from the apex of the first measured flight).
      for (int& index : fit.simulated.impact_index) index += plan.first_matched_impact;
    }
    if (&plan == &plans.front()) {
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

  const int duplicates = summary.uncertainty.duplicates;
  auto uncertainty = internal::EstimateUncertainty(weighted, options, map, minimized.x);
  summary.uncertainty = std::move(uncertainty.summary);
  summary.uncertainty.duplicates = duplicates;
  for (size_t i = 0; i < map.size(); ++i) {
    auto& parameter = summary.parameters[i];
    parameter.confidence_interval = uncertainty.parameters[i].interval;
    parameter.interval_clipped = uncertainty.parameters[i].clipped;
    parameter.standard_error = uncertainty.parameters[i].standard_error;
  }
  if (!summary.uncertainty.per_impact_estimable && summary.uncertainty.available &&
      sequences.size() == 1) {
    summary.warnings.push_back(
        "with one fitted impact the impact-to-impact scatter cannot be estimated, so the interval "
        "holds timing noise only and is too narrow; fit three or more impacts (`first_n=3`) or "
        "give several recordings");
  }
  summary.contact_speed_mps =
      std::sqrt(2 * options.drop.gravity_mps2 * plans.front().release_height_m);
  summary.contact_duration_s =
      ContactDurationS(summary.law, options.drop.ball, summary.contact_speed_mps);
  if (auto warning = ContactDurationWarning(summary.law, options.drop.ball, options.ball_preset,
                                            summary.contact_speed_mps);
      !warning.empty())
    summary.warnings.push_back(std::move(warning));
  summary.adequacy = TestAdequacy(options, summary.law, plans, comparing);
  if (summary.adequacy.trend) summary.warnings.push_back(summary.adequacy.message);
  for (const auto& parameter : summary.parameters) {
    if (!parameter.at_bound) continue;
    const bool low =
        parameter.value - parameter.range.lower < parameter.range.upper - parameter.value;
    summary.warnings.push_back(
        parameter.name + " = " + Format("%.6g", parameter.value) + " is at the " +
        (low ? "lower" : "upper") + " edge of its search range, so the data ask for " +
        (low ? "less" : "more") + " damping than the law allows; check the drop height and the " +
        "first impact (bouncecal analyze), or rank other laws with `compare_laws`");
  }

  if (options.analytic_check) {
    summary.check =
        internal::MakeCheck(options, map, summary.law, plans, summary.uncertainty, summary.stop);
    if (summary.check.warning) summary.warnings.push_back(summary.check.message);
  }
  summary.total_time_s = SecondsSince(start);
  return summary;
}

}  // namespace

FitSummary Fit(const std::vector<MeasuredSequence>& sequences, const FitOptions& options) {
  if (!options.contact_duration_s) return FitSequences(sequences, options, /*comparing=*/false);
  if (!options.ball_given) {
    throw OptionError({"contact_duration_s", "ball"},
                      "contact_duration_s needs the ball (its mass sets the stiffness that gives "
                      "that duration); give `ball`, or its diameter and mass");
  }
  FitOptions fixed = options;
  fixed.contact_duration_s.reset();
  const double release_speed_mps =
      std::sqrt(2 * fixed.drop.gravity_mps2 * fixed.drop.drop_height_m);
  fixed.drop.law = WithContactDuration(fixed.drop.law, fixed.drop.ball, release_speed_mps,
                                       *options.contact_duration_s);
  const auto first = FitSequences(sequences, fixed, /*comparing=*/false);
  fixed.drop.law = WithContactDuration(first.law, fixed.drop.ball, first.contact_speed_mps,
                                       *options.contact_duration_s);
  return FitSequences(sequences, fixed, /*comparing=*/false);
}

namespace {

// The data the objective compares over the distinct sequences (FitSummary::data_points before
// fitting): one eta-bar per recording, or every fitted flight.
int ObjectiveDataPoints(const std::vector<MeasuredSequence>& input, const FitOptions& options) {
  std::vector<std::string> ignored;
  int duplicates = 0;
  const auto plans = MakePlans(DistinctSequences(input, ignored, duplicates), options);
  int points = 0;
  for (const auto& plan : plans)
    points += options.objective == FitObjective::kMeanEnergyLoss ? 1 : plan.impacts_needed - 1;
  return points;
}

// The objective the comparison fits on (see CompareLaws), and the note saying why when it is not
// the one asked for.
FitObjective RankableObjective(const std::vector<MeasuredSequence>& sequences,
                               const std::vector<dem::ContactLawKind>& laws,
                               const FitOptions& options, bool objective_given, std::string& note) {
  size_t most = 0, fewest = std::numeric_limits<size_t>::max();
  dem::ContactLawKind widest = laws.front();
  for (auto kind : laws) {
    const size_t count = DefaultFittedParameters(kind).size();
    fewest = std::min(fewest, count);
    if (count > most) {
      most = count;
      widest = kind;
    }
  }
  const int points = ObjectiveDataPoints(sequences, options);
  if (points > static_cast<int>(most)) return options.objective;
  const std::string law(dem::ToString(widest));
  const std::string counts = std::to_string(points) + " datum(s) against " + std::to_string(most) +
                             " fitted parameter(s) of " + law;
  if (options.objective == FitObjective::kMeanEnergyLoss && !objective_given) {
    FitOptions intervals = options;
    intervals.objective = FitObjective::kIntervals;
    int interval_points = 0;
    try {
      interval_points = ObjectiveDataPoints(sequences, intervals);
    } catch (const ConfigError&) {
      // Too short for intervals as well: refused below with the numbers of the default.
    }
    if (interval_points > static_cast<int>(most)) {
      note = "the default objective mean-energy-loss gives " + counts +
             ", which leaves no degree of freedom to rank on, so every law is fitted on every "
             "flight interval instead (`objective=intervals`, " +
             std::to_string(interval_points) + " data)";
      return FitObjective::kIntervals;
    }
  }
  throw ConfigError(
      "`compare_laws`: objective " + std::string(ToString(options.objective)) + " gives " + counts +
      ", so every law fits exactly and the ranking would count parameters only; " +
      (options.objective == FitObjective::kMeanEnergyLoss
           ? "fit every flight interval (`objective=intervals`) or add recordings"
           : "use a longer recording (more bounces) or add recordings") +
      (points > static_cast<int>(fewest)
           ? ", or leave the laws with " + std::to_string(most) + " parameters out (`laws`)"
           : ""));
}

}  // namespace

std::string GoodnessOfFitWarning(const FitSummary& fit) {
  if (fit.degrees_of_freedom < 1) return "";
  const double dof = fit.degrees_of_freedom;
  const double tail = (1 - kGoodnessOfFitLevel) / 2;
  const double low = internal::ChiSquareQuantile(tail, dof);
  const double high = internal::ChiSquareQuantile(1 - tail, dof);
  if (fit.residual >= low && fit.residual <= high) return "";
  const bool above = fit.residual > high;
  char text[600];
  std::snprintf(
      text, sizeof text,
      "%s: chi^2/dof = %.3g (chi^2 = %.4g over %d dof) lies %s the central %g %% of the "
      "chi-square distribution for %d dof (%.4g to %.4g): %s",
      std::string(dem::ToString(fit.law.kind)).c_str(), fit.residual / dof, fit.residual,
      fit.degrees_of_freedom, above ? "above" : "below", 100 * kGoodnessOfFitLevel,
      fit.degrees_of_freedom, low, high,
      above ? "the law misses the data by more than their timing uncertainties, so its dBIC are "
              "overstated about that many times; look at the residuals (`plot`) and trust only "
              "dBIC well beyond chi^2/dof"
            : "the data agree better than their stated uncertainties allow (overstated timing "
              "uncertainties), so dBIC are understated; check the onset uncertainties "
              "(bouncecal analyze)");
  return text;
}

LawComparison CompareLaws(const std::vector<MeasuredSequence>& sequences,
                          const std::vector<dem::ContactLawKind>& laws, const FitOptions& options,
                          bool objective_given) {
  std::vector<dem::ContactLawKind> fittable;
  for (auto kind : laws) {
    if (!DefaultFittedParameters(kind).empty()) fittable.push_back(kind);
  }
  if (fittable.empty()) throw ConfigError("none of the laws to compare has a damping parameter");
  if (sequences.empty()) throw ConfigError("no recording to fit; give at least one");
  FitOptions checked = options;  // the options' own problems first, as Fit would name them
  checked.drop.law = {fittable.front(), {}};
  ValidateOptions(checked);
  LawComparison comparison;
  FitOptions ranked = options;
  ranked.objective =
      RankableObjective(sequences, fittable, options, objective_given, comparison.objective_note);
  std::vector<FitSummary> fits(fittable.size());
  std::vector<std::exception_ptr> errors(fittable.size());
  // One law per item of the project's worker pool; each fit writes only its own slot, so the
  // ranking does not depend on which thread ran which law.
  auto fit_law = [&](std::int64_t item) {
    const auto i = static_cast<size_t>(item);
    {
      try {
        FitOptions law_options = ranked;
        law_options.drop.law = {fittable[i], {}};
        // Keep the parameters this law shares by name (stiffness_n_per_m for the linear laws).
        const auto& given = options.drop.law.parameters;
        for (const auto& spec : dem::ParameterSpecs(fittable[i])) {
          if (auto it = given.find(spec.name); it != given.end())
            law_options.drop.law.parameters[it->first] = it->second;
        }
        law_options.fitted_parameters.clear();
        law_options.ranges.clear();
        law_options.uncertainty.threads = 1;  // the laws already share the threads
        fits[i] = FitSequences(sequences, law_options, /*comparing=*/true);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const int threads = std::min<int>(options.uncertainty.threads, static_cast<int>(fittable.size()));
  WorkerPool pool(threads);
  pool.ParallelForEach(static_cast<std::int64_t>(fittable.size()), fit_law);
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  std::stable_sort(fits.begin(), fits.end(),
                   [](const FitSummary& a, const FitSummary& b) { return a.bic < b.bic; });
  for (const auto& fit : fits) {
    if (auto warning = GoodnessOfFitWarning(fit); !warning.empty())
      comparison.warnings.push_back(std::move(warning));
  }
  comparison.fits = std::move(fits);
  return comparison;
}

}  // namespace bouncecal::calibrate
