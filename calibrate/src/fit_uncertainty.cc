#include "fit_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "bouncecal/calibrate/contact_stiffness.h"
#include "bouncecal/error.h"
#include "sandwich.h"
#include "student_t.h"

namespace bouncecal::calibrate::internal {
namespace {

// Onset step of the numerical derivatives: far below any timing noise, far above the rounding of
// onsets (2e-15 s at 10 s, 5e-13 s at an hour), so the central difference of the data, which are
// smooth closed forms of the onsets, is exact to 2e-8 relative (5e-6 an hour into a file).
constexpr double kOnsetStepS = 1e-7;
// Relative step of the first flight (the release height of an unknown-height fit) and of the drop
// height: the simulated drop's step size follows the impact speed, so a tiny change would measure
// the engine's rounding; 1e-3 is far above it and small against the response's curvature.
constexpr double kRelativeStep = 1e-3;
// The level of the speed-trend test (model_adequacy.h), which picks the law the scatter is
// measured about.
constexpr double kTrendLevel = 0.99;

Eigen::VectorXd ToVector(const std::vector<double>& values) {
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

std::optional<double> DropHeightOf(const SequencePlan& plan) {
  return plan.known_drop_height ? std::optional<double>(plan.release_height_m) : std::nullopt;
}

Eigen::VectorXd ModelAt(const SequencePlan& plan, const dem::ContactLawConfig& law,
                        const FitOptions& options) {
  return ToVector(Terms(plan, SimulateSequence(law, plan, options), options).model);
}

// The parameter step of the central difference, in optimiser coordinates. A fixed step grid makes
// eta(gamma) jagged on the scale of 1e-3 of the range, so its slope is taken over a wider span.
double ParameterStep(const FitOptions& options, const ParameterMap& map, size_t i) {
  const double width = map.UpperBounds()[i] - map.LowerBounds()[i];
  return (options.drop.fixed_step_grid ? 0.05 : 0.005) * width;
}

struct Linearized {
  SequenceLinearization linearization;
  ImpactResiduals impacts;
  std::vector<size_t> used;
  SimulatedSequence simulated;
};

// Residuals of the used eta_k at the law and their timing covariance; with `full`, everything
// else the sandwich needs.
Linearized Linearize(const SequencePlan& plan, const FitOptions& options, const ParameterMap& map,
                     const std::vector<double>& x, bool full) {
  Linearized result;
  const auto law = map.Apply(options.drop.law, x);
  result.simulated = SimulateSequence(law, plan, options);
  const auto terms = Terms(plan, result.simulated, options);
  const auto terms_count = static_cast<Eigen::Index>(terms.model.size());
  auto& linear = result.linearization;
  linear.residual = ToVector(terms.model) - ToVector(terms.data);
  linear.weights = ToVector(terms.sigma).array().square().inverse();

  // Used impacts the simulated ball also made: where it came to rest early there is no simulated
  // eta_k to compare with (that misfit is the objective's business, not scatter).
  for (size_t j : UsedEnergyLossEntries(plan)) {
    if (j < result.simulated.energy_loss.size()) result.used.push_back(j);
  }
  const auto used_count = static_cast<Eigen::Index>(result.used.size());
  result.impacts.residual.resize(used_count);
  for (Eigen::Index u = 0; u < used_count; ++u) {
    const size_t j = result.used[static_cast<size_t>(u)];
    result.impacts.residual[u] = plan.measured.energy_loss[j] - result.simulated.energy_loss[j];
  }

  // Onsets up to the last one the objective compares; later ones change nothing.
  const int last = plan.first_matched_impact + plan.impacts_needed - 1;
  const Eigen::Index onsets = last + 1;
  Eigen::MatrixXd eta_by_onset = Eigen::MatrixXd::Zero(used_count, onsets);
  linear.onsets = Eigen::MatrixXd::Zero(terms_count, onsets);
  linear.onset_variance.resize(onsets);
  for (Eigen::Index m = 0; m < onsets; ++m) {
    const double sigma = plan.impacts[static_cast<size_t>(m)].uncertainty_s;
    linear.onset_variance[m] = sigma * sigma;
    Eigen::VectorXd data[2], eta[2];
    for (int side = 0; side < 2; ++side) {
      MeasuredSequence moved;
      moved.source = plan.source;
      moved.impacts = plan.impacts;
      moved.impacts[static_cast<size_t>(m)].onset_s += side == 0 ? kOnsetStepS : -kOnsetStepS;
      const SequencePlan moved_plan = MakePlan(moved, options, DropHeightOf(plan));
      data[side] = ToVector(Terms(moved_plan, result.simulated, options).data);
      eta[side].resize(used_count);
      for (Eigen::Index u = 0; u < used_count; ++u)
        eta[side][u] = moved_plan.measured.energy_loss[result.used[static_cast<size_t>(u)]];
    }
    linear.onsets.col(m) = -(data[0] - data[1]) / (2 * kOnsetStepS);
    eta_by_onset.col(m) = (eta[0] - eta[1]) / (2 * kOnsetStepS);
  }
  // A shift common to the onsets before impact m (TimedImpact::incoming_flight_uncertainty_s)
  // moves everything by the sum of their columns: one more independent timing source each.
  std::vector<Eigen::Index> shifted_flights;
  for (Eigen::Index m = 1; m < onsets; ++m) {
    if (plan.impacts[static_cast<size_t>(m)].incoming_flight_uncertainty_s > 0)
      shifted_flights.push_back(m);
  }
  const auto shifts = static_cast<Eigen::Index>(shifted_flights.size());
  const auto with_shifts = [&](const Eigen::MatrixXd& by_onset) {
    Eigen::MatrixXd by_source(by_onset.rows(), onsets + shifts);
    by_source.leftCols(onsets) = by_onset;
    for (Eigen::Index s = 0; s < shifts; ++s)
      by_source.col(onsets + s) =
          by_onset.leftCols(shifted_flights[static_cast<size_t>(s)]).rowwise().sum();
    return by_source;
  };
  Eigen::VectorXd source_variance(onsets + shifts);
  source_variance.head(onsets) = linear.onset_variance;
  for (Eigen::Index s = 0; s < shifts; ++s) {
    const double sigma = plan.impacts[static_cast<size_t>(shifted_flights[static_cast<size_t>(s)])]
                             .incoming_flight_uncertainty_s;
    source_variance[onsets + s] = sigma * sigma;
  }
  const Eigen::MatrixXd eta_by_source = with_shifts(eta_by_onset);
  result.impacts.timing_covariance =
      eta_by_source * source_variance.asDiagonal() * eta_by_source.transpose();
  if (!full) {
    linear.onset_variance = source_variance;
    linear.onsets = with_shifts(linear.onsets);
    return result;
  }

  const size_t p = map.size();
  linear.parameters.resize(terms_count, static_cast<Eigen::Index>(p));
  for (size_t i = 0; i < p; ++i) {
    const double step = ParameterStep(options, map, i);
    auto above = x, below = x;
    above[i] = std::min(x[i] + step, map.UpperBounds()[i]);
    below[i] = std::max(x[i] - step, map.LowerBounds()[i]);
    linear.parameters.col(static_cast<Eigen::Index>(i)) =
        (ModelAt(plan, map.Apply(options.drop.law, above), options) -
         ModelAt(plan, map.Apply(options.drop.law, below), options)) /
        (above[i] - below[i]);
  }

  if (!plan.known_drop_height) {
    // The release is the apex of the first measured flight, so the model moves with t_0 and t_1.
    const double first = plan.measured.intervals_s.front();
    const double g = options.drop.gravity_mps2;
    Eigen::VectorXd model[2];
    for (int side = 0; side < 2; ++side) {
      SequencePlan moved = plan;
      const double flight = first * (1 + (side == 0 ? kRelativeStep : -kRelativeStep));
      moved.release_height_m = g * flight * flight / 8.0;
      model[side] = ModelAt(moved, law, options);
    }
    const Eigen::VectorXd by_flight = (model[0] - model[1]) / (2 * kRelativeStep * first);
    linear.onsets.col(0) -= by_flight;
    linear.onsets.col(1) += by_flight;
  }

  // A change d eta at impact k changes e_k by -d eta / (2 e_k) and stretches every later flight
  // by the factor e_k'/e_k, so onset m > k moves by (t_m - t_k) d e_k / e_k.
  const auto& measured = plan.measured;
  linear.jitter =
      Eigen::MatrixXd::Zero(onsets, static_cast<Eigen::Index>(measured.energy_loss.size()));
  for (size_t j = 0; j < measured.energy_loss.size(); ++j) {
    const int k = measured.impact_index[j];
    const double e = measured.restitution[j];
    for (int m = k + 1; m <= last; ++m) {
      linear.jitter(m, static_cast<Eigen::Index>(j)) =
          -(plan.impacts[static_cast<size_t>(m)].onset_s -
            plan.impacts[static_cast<size_t>(k)].onset_s) /
          (2 * e * e);
    }
  }

  if (plan.known_drop_height && plan.drop_height_uncertainty_m > 0) {
    // Forward difference: a higher drop can never turn the first rebound into one above it.
    const double step = kRelativeStep * plan.release_height_m;
    MeasuredSequence sequence;
    sequence.source = plan.source;
    sequence.impacts = plan.impacts;
    const SequencePlan higher = MakePlan(sequence, options, plan.release_height_m + step);
    const auto higher_terms = Terms(higher, SimulateSequence(law, higher, options), options);
    const Eigen::VectorXd residual = ToVector(higher_terms.model) - ToVector(higher_terms.data);
    // Per sigma of this plan's height, so plans whose heights were measured apart combine.
    linear.drop_height = (residual - linear.residual) / step * plan.drop_height_uncertainty_m;
    linear.drop_height_group = plan.drop_height_group;
  }
  // The shifts' columns come last, after the first flight's share above; an eta_k's jitter
  // moves onsets, never a shift.
  linear.onsets = with_shifts(linear.onsets);
  linear.onset_variance = source_variance;
  linear.jitter.conservativeResize(onsets + shifts, Eigen::NoChange);
  linear.jitter.bottomRows(shifts).setZero();
  return result;
}

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

double Mean(const Eigen::VectorXd& values) { return values.size() ? values.mean() : 0.0; }

double SampleSd(const std::vector<double>& values) {
  if (values.size() < 2) return 0;
  double mean = 0;
  for (double v : values) mean += v / static_cast<double>(values.size());
  double squares = 0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

// The per-impact scatter of every measured impact about the law the trend test settles on: one
// speed line per sequence when its slope is claimed (a trend is not scatter), one constant per
// sequence otherwise (the slope would cost a degree of freedom for nothing), or about a constant
// when there are too few impacts for a slope.
ScatterPosterior EveryImpactScatter(const std::vector<SequencePlan>& plans,
                                    const FitOptions& options, const dem::ContactLawConfig& law) {
  const auto impacts = EveryImpactResiduals(plans, options, law);
  // The trend is decided as the adequacy test decides it (stated timing sds); the interval's
  // posterior then also scales the stated timing sds by what the residuals show
  // (FitScatterPosterior's scale_timing).
  const auto with_slope = FitScatterPosterior(impacts, /*with_slope=*/true);
  const bool trend =
      with_slope.ok && with_slope.dof >= 2 && with_slope.SlopeExcludesZero(kTrendLevel);
  // One degree of freedom (a short sequence's two energy losses) leaves tau's posterior wide but
  // proper: its grid ends at tau = 1 (eta lies in [0, 1]; scatter_posterior.cc), and the interval
  // mixes over it.
  // The moment estimate that stood in for it there was 0 wherever the two losses agreed within
  // what the stated timing explains, and the interval then held timing alone (t = 1.96): drops
  // of 3 impacts with 3 % scatter of e and onsets stated +-1 ms, as a codec's table states them,
  // were covered 78-81 times in 100 (the coverage suite's lead_e050_j4_s4109 as AAC 128k:
  // [0.6199, 0.6200] against the material's 0.5995); with the posterior 99-100.
  return FitScatterPosterior(impacts, trend, /*scale_timing=*/true);
}

// The half-width q of the level interval of a parameter whose error, given tau_w, is Student t
// with `dof[j]` degrees of freedom and variance `variance[j]`, mixed over tau_w's posterior
// `weight[j]`: sum_j weight_j P(|T_j| sqrt(variance_j) <= q) = level, by bisection between the
// smallest and largest of the components' own half-widths.
double MixtureHalfWidth(const std::vector<double>& weight, const std::vector<double>& variance,
                        const std::vector<double>& dof, double level) {
  const double tail = 0.5 + level / 2;
  double low = std::numeric_limits<double>::infinity(), high = 0;
  for (size_t j = 0; j < weight.size(); ++j) {
    const double half = StudentTQuantile(tail, dof[j]) * std::sqrt(variance[j]);
    low = std::min(low, half);
    high = std::max(high, half);
  }
  const auto inside = [&](double q) {
    double probability = 0;
    for (size_t j = 0; j < weight.size(); ++j) {
      if (weight[j] < 1e-14) continue;
      const double t = q / std::sqrt(variance[j]);
      probability += weight[j] * (2 * StudentTCdf(t, dof[j]) - 1);
    }
    return probability;
  };
  for (int i = 0; i < 60 && high - low > 1e-12 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (inside(middle) < level ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

// The degrees of freedom at which Student's t quantile equals t (infinite when t is at or below
// the normal quantile), for reporting a mixture as an equivalent t interval.
double EquivalentDof(double t, double tail) {
  if (!(t > NormalQuantile(tail))) return std::numeric_limits<double>::infinity();
  double low = std::log(0.05), high = std::log(1e7);
  for (int i = 0; i < 80; ++i) {
    const double middle = 0.5 * (low + high);
    (StudentTQuantile(tail, std::exp(middle)) > t ? low : high) = middle;
  }
  return std::exp(0.5 * (low + high));
}

}  // namespace

namespace {

// The contact made this much longer, to see how the drop's eta_k depend on its duration.
constexpr double kContactLengthening = 1.5;

// The drop's eta_k with the law's contact lengthened (its elastic parameter softened,
// WithContactDuration); empty where the law has no closed-form duration or the softer parameter
// is outside its range.
std::vector<double> SimulateWithLongerContact(const dem::ContactLawConfig& law,
                                              const SequencePlan& plan, const FitOptions& options) {
  const double speed = IncomingSpeedMps(plan, plan.first_matched_impact, options.drop.gravity_mps2);
  const auto duration = ContactDurationS(law, options.drop.ball, speed);
  if (!duration || !(*duration > 0)) return {};
  try {
    const auto softer =
        WithContactDuration(law, options.drop.ball, speed, *duration * kContactLengthening);
    return SimulateSequence(softer, plan, options).energy_loss;
  } catch (const ConfigError&) {
    return {};
  }
}

}  // namespace

std::vector<AdequacyImpact> EveryImpactResiduals(const std::vector<SequencePlan>& plans,
                                                 const FitOptions& options,
                                                 const dem::ContactLawConfig& law) {
  std::vector<AdequacyImpact> impacts;
  for (size_t r = 0; r < plans.size(); ++r) {
    SequencePlan whole = plans[r];
    whole.impacts_needed = static_cast<int>(whole.impacts.size()) - whole.first_matched_impact;
    const auto simulated = SimulateSequence(law, whole, options).energy_loss;
    const auto longer = SimulateWithLongerContact(law, whole, options);
    const auto& measured = whole.measured;
    for (size_t j = 0; j < measured.energy_loss.size() && j < simulated.size(); ++j) {
      const int k = measured.impact_index[j];
      const double speed = IncomingSpeedMps(whole, k, options.drop.gravity_mps2);
      AdequacyImpact impact{static_cast<int>(r), speed, measured.energy_loss[j] - simulated[j],
                            std::pow(measured.energy_loss_uncertainty[j], 2)};
      if (j < longer.size()) {
        impact.contact_sensitivity = (longer[j] - simulated[j]) / std::log(kContactLengthening);
      }
      impacts.push_back(impact);
    }
  }
  return impacts;
}

ScatterEstimate ScatterAt(const std::vector<SequencePlan>& plans, const FitOptions& options,
                          const ParameterMap& map, const std::vector<double>& x) {
  std::vector<ImpactResiduals> impacts;
  for (const auto& plan : plans)
    impacts.push_back(Linearize(plan, options, map, x, /*full=*/false).impacts);
  const auto every = EveryImpactScatter(plans, options, map.Apply(options.drop.law, x));
  return EstimateScatter(impacts, static_cast<int>(map.size()), &every);
}

namespace {

// The paper's protocol: eta-bar per sequence, across sequences mean +- sd and the interval of
// the mean, into `summary`.
void SummariseRecordings(const std::vector<SequencePlan>& plans,
                         const std::vector<Linearized>& linearized,
                         const std::vector<ImpactResiduals>& impacts,
                         const ScatterEstimate& scatter, UncertaintySummary& summary) {
  std::vector<double> means;
  double mean_variance = 0;
  for (size_t r = 0; r < plans.size(); ++r) {
    RecordingSpread spread;
    spread.source = plans[r].source;
    const auto& used = linearized[r].used;
    spread.impacts_used = static_cast<int>(used.size());
    double sum = 0;
    for (size_t j : used) sum += plans[r].measured.energy_loss[j];
    const double n = std::max<double>(1.0, static_cast<double>(used.size()));
    spread.energy_loss_mean = sum / n;
    const double variance = scatter.within_variance / n +
                            scatter.timing_variance_scale * TimingVarianceOfMean(impacts[r]);
    spread.energy_loss_mean_uncertainty = std::sqrt(variance);
    mean_variance += variance;
    const auto& residual = impacts[r].residual;
    if (residual.size() >= 2) {
      spread.energy_loss_scatter =
          std::sqrt((residual.array() - Mean(residual)).square().sum() / (residual.size() - 1.0));
    }
    means.push_back(spread.energy_loss_mean);
    summary.recordings.push_back(std::move(spread));
  }
  const double count = static_cast<double>(plans.size());
  for (double mean : means) summary.energy_loss_mean += mean / count;
  summary.energy_loss_mean_uncertainty =
      std::sqrt(mean_variance / (count * count) + scatter.between_variance / count);
  if (plans.size() >= 2) {
    const double sd = SampleSd(means);
    summary.energy_loss_sd_across = sd;
    const double tail = 0.5 + summary.confidence_level / 2;
    const double half = StudentTQuantile(tail, count - 1) * sd / std::sqrt(count);
    summary.energy_loss_mean_interval =
        std::make_pair(summary.energy_loss_mean - half, summary.energy_loss_mean + half);
  }
}

// One parameter's variance, in the sandwich's parts c_w, c_b (per unit of the within and
// between variances) and its known timing and drop-height parts.
struct ParameterVarianceParts {
  double c_w = 0, c_b = 0, timing = 0, height = 0;
};

struct ParameterVariance {
  double within = 0, between = 0, timing = 0, total = 0, dof = 0;
};

// The variance of the parameter and Satterthwaite's (1946) degrees of freedom of its estimated
// parts at a per-impact variance tau_w^2 with `within_dof` (0: taken as known). The stated
// timing and drop-height variances are known.
// `timing_scale2` multiplies every stated timing variance (the posterior's phi^2, 1 without it).
ParameterVariance VarianceAt(const ScatterEstimate& scatter, const ParameterVarianceParts& parts,
                             double within_variance, int within_dof, double timing_scale2) {
  ParameterVariance result;
  double between_variance = scatter.between_variance;
  if (scatter.between_dof > 0) {
    between_variance =
        std::max(0.0, scatter.between_mean_square - within_variance * scatter.mean_inverse_count -
                          timing_scale2 * scatter.mean_timing_variance);
  }
  result.within = within_variance * parts.c_w;
  result.between = between_variance * parts.c_b;
  result.timing = timing_scale2 * parts.timing;
  result.total = result.timing + result.within + result.between + parts.height;
  double denominator = 0;
  if (between_variance > 0) {
    // tau_b^2 = MS_b - mean(1/n) tau_w^2 - timing: the variance is a combination of the two
    // estimated mean squares, so Satterthwaite's degrees of freedom are those of that
    // combination (in a balanced design the within part cancels and MS_b's R - 1 remain).
    const double a_w = (parts.c_w - parts.c_b * scatter.mean_inverse_count) * within_variance;
    const double a_b = parts.c_b * scatter.between_mean_square;
    if (within_dof > 0) denominator += a_w * a_w / within_dof;
    denominator += a_b * a_b / scatter.between_dof;
  } else if (within_dof > 0) {
    denominator += result.within * result.within / within_dof;
  }
  result.dof = denominator > 0 ? result.total * result.total / denominator
                               : std::numeric_limits<double>::infinity();
  return result;
}

// The interval's half-width, its t and effective dof for one parameter.
struct HalfWidth {
  double half = 0, t = 0, dof = 0;
};

HalfWidth IntervalHalfWidth(const ScatterEstimate& scatter, const ParameterVarianceParts& parts,
                            const ParameterVariance& point, double confidence_level) {
  const double tail = 0.5 + confidence_level / 2;
  HalfWidth width;
  width.dof = point.dof;
  if (scatter.within_from_every_impact) {
    // tau_w integrated over its posterior (scatter_posterior.h) instead of one estimate with
    // Satterthwaite's dof: given tau_w the within part is known, the between part keeps its
    // dof.
    const auto& posterior = scatter.within_posterior;
    std::vector<double> variance, dofs;
    for (size_t j = 0; j < posterior.tau.size(); ++j) {
      const double tau = posterior.tau[j], phi = posterior.timing_scale[j];
      const auto node = VarianceAt(scatter, parts, tau * tau, 0, phi * phi);
      variance.push_back(node.total);
      dofs.push_back(node.dof);
    }
    width.half = MixtureHalfWidth(posterior.weight, variance, dofs, confidence_level);
    width.t = point.total > 0 ? width.half / std::sqrt(point.total) : 0.0;
    width.dof = EquivalentDof(width.t, tail);
  } else {
    width.t = StudentTQuantile(tail, point.dof);
    width.half = width.t * std::sqrt(point.total);
  }
  return width;
}

// UncertaintySummary::model: what the interval is made of, in one line.
std::string DescribeModel(const ScatterEstimate& scatter, const UncertaintySummary& summary,
                          const std::vector<SequencePlan>& plans, const ParameterMap& map,
                          bool height_uncertain) {
  std::string model = "linearised through the DEM drops at the fit: ";
  if (scatter.within_from_every_impact) {
    const auto& posterior = scatter.within_posterior;
    model += "per-impact scatter of eta_k about the law" +
             std::string(posterior.with_slope ? " and a speed trend" : "") + " beyond timing (sd " +
             Format("%.2g", summary.per_impact_scatter) + ", 90 % between " +
             Format("%.2g", posterior.TauQuantile(0.05)) + " and " +
             Format("%.2g", posterior.TauQuantile(0.95)) + ", " +
             std::to_string(scatter.within_dof) +
             " dof, from every measured impact; the interval integrates over it)";
    if (posterior.timing_scaled) {
      model += " + onset timing (each onset's stated sigma times " +
               Format("%.2g", posterior.TimingScaleQuantile(0.5)) + ", 90 % between " +
               Format("%.2g", posterior.TimingScaleQuantile(0.05)) + " and " +
               Format("%.2g", posterior.TimingScaleQuantile(0.95)) +
               ", from the same impacts, integrated over jointly)";
    }
  } else if (scatter.within_estimable) {
    // The scatter beyond what the onsets' timing explains (ScatterEstimate: the excess, 0 when
    // timing explains all of it), not the raw sd the report prints beside eta-bar.
    model += "per-impact scatter of eta_k about the law beyond timing (sd " +
             Format("%.2g", summary.per_impact_scatter) + ", " +
             std::to_string(scatter.within_dof) + " dof, from the fitted impacts)";
  } else {
    model += "per-impact scatter not estimable (one fitted impact per recording)";
  }
  if (!(scatter.within_from_every_impact && scatter.within_posterior.timing_scaled))
    model += " + onset timing (each onset's stated sigma)";
  if (plans.size() >= 2) {
    model += " + between-recording spread (sd " + Format("%.2g", summary.between_recording_sd) +
             ", " + std::to_string(scatter.between_dof) + " dof)";
  }
  if (height_uncertain) {
    double largest = 0;
    for (const auto& plan : plans) largest = std::max(largest, plan.drop_height_uncertainty_m);
    model += " + drop height (+- " + Format("%.3g", largest) + " m)";
  }
  model +=
      "; " + Format("%.0f", 100 * summary.confidence_level) +
      " % interval, t = " + Format("%.3g", summary.t_quantile) +
      (std::isinf(summary.effective_dof)
           ? std::string(" (known variances only)")
           : " (as Student's at " + Format("%.1f", summary.effective_dof) + " effective dof)") +
      "; variance of " + map.names().front() + ": scatter " +
      Format("%.0f", 100 * summary.scatter_share) + " %, timing " +
      Format("%.0f", 100 * summary.timing_share) + " %";
  if (plans.size() >= 2) model += ", between " + Format("%.0f", 100 * summary.between_share) + " %";
  if (height_uncertain)
    model += ", drop height " + Format("%.0f", 100 * summary.drop_height_share) + " %";
  return model;
}

}  // namespace

FitUncertainty EstimateUncertainty(const std::vector<SequencePlan>& plans,
                                   const FitOptions& options, const ParameterMap& map,
                                   const std::vector<double>& x) {
  FitUncertainty result;
  auto& summary = result.summary;
  summary.confidence_level = options.uncertainty.confidence_level;
  summary.sequences = static_cast<int>(plans.size());
  result.parameters.resize(map.size());

  std::vector<Linearized> linearized;
  std::vector<SequenceLinearization> linearizations;
  std::vector<ImpactResiduals> impacts;
  for (const auto& plan : plans) {
    linearized.push_back(Linearize(plan, options, map, x, /*full=*/true));
    linearizations.push_back(linearized.back().linearization);
    impacts.push_back(linearized.back().impacts);
    summary.impacts_used += static_cast<int>(linearized.back().used.size());
  }
  const auto every = EveryImpactScatter(plans, options, map.Apply(options.drop.law, x));
  const ScatterEstimate scatter = EstimateScatter(impacts, static_cast<int>(map.size()), &every);
  summary.per_impact_estimable = scatter.within_estimable;
  summary.per_impact_scatter = std::sqrt(scatter.within_variance);
  summary.per_impact_dof = scatter.within_dof;
  summary.between_recording_sd = std::sqrt(scatter.between_variance);
  summary.between_dof = scatter.between_dof;
  SummariseRecordings(plans, linearized, impacts, scatter, summary);

  const CovarianceParts covariance = SandwichCovariance(linearizations);
  if (!covariance.ok) {
    summary.message = std::to_string(map.size()) +
                      " fitted parameters are not separately determined by these data (the "
                      "Gauss-Newton matrix is singular or has condition number " +
                      Format("%.2g", covariance.condition) + "), so no linear interval applies";
    summary.model = "none: " + summary.message;
    return result;
  }
  summary.available = true;
  for (size_t r = 0; r < plans.size(); ++r) {
    const Eigen::VectorXd step = SingleSequenceStep(linearizations[r]);
    if (step.size() == 0) continue;
    for (size_t i = 0; i < map.size(); ++i)
      summary.recordings[r].parameter_values.push_back(
          map.Value(i, x[i] + step[static_cast<Eigen::Index>(i)]));
  }

  // The drop-height parts are per sigma of each plan's own height (Linearize).
  const bool height_uncertain = std::any_of(plans.begin(), plans.end(), [](const auto& plan) {
    return plan.known_drop_height && plan.drop_height_uncertainty_m > 0;
  });
  for (size_t i = 0; i < map.size(); ++i) {
    const auto d = static_cast<Eigen::Index>(i);
    const ParameterVarianceParts parts{covariance.within(d, d), covariance.between(d, d),
                                       covariance.timing(d, d),
                                       height_uncertain ? covariance.drop_height(d, d) : 0.0};
    const auto point = VarianceAt(scatter, parts, scatter.within_variance, scatter.within_dof,
                                  scatter.timing_variance_scale);
    const HalfWidth width = IntervalHalfWidth(scatter, parts, point, summary.confidence_level);
    auto& parameter = result.parameters[i];
    const double low = x[i] - width.half, high = x[i] + width.half;
    parameter.clipped = low < map.LowerBounds()[i] || high > map.UpperBounds()[i];
    parameter.interval = std::make_pair(map.Value(i, low), map.Value(i, high));
    const double value = map.Value(i, x[i]);
    parameter.standard_error =
        (map.ranges()[i].log_scale ? value : 1.0) * std::sqrt(std::max(point.total, 0.0));
    if (i == 0) {
      const double share = point.total > 0 ? 1.0 / point.total : 0.0;
      summary.timing_share = point.timing * share;
      summary.scatter_share = point.within * share;
      summary.between_share = point.between * share;
      summary.drop_height_share = parts.height * share;
      summary.effective_dof = width.dof;
      summary.t_quantile = width.t;
    }
  }
  summary.model = DescribeModel(scatter, summary, plans, map, height_uncertain);
  return result;
}

}  // namespace bouncecal::calibrate::internal
