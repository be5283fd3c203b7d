#include "analytic_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate::internal {
namespace {

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// eta-bar (first N) of the reference sequence simulated with `law`, optionally with another
// integrator or without drag.
double SimulatedEnergyLossMean(const FitOptions& options, const dem::ContactLawConfig& law,
                               const SequencePlan& plan, bool drag,
                               std::optional<dem::Integrator> integrator = {}) {
  FitOptions variant = options;
  variant.drop.drag.enabled = drag && options.drop.drag.enabled;
  return internal::MeanOfFirst(
      internal::SimulateSequence(law, plan, variant, integrator).energy_loss,
      internal::EtaBarCount(plan, options));
}

// The incoming speeds of the impacts in a recording's measured eta-bar (its first N energy
// losses), where the closed forms of speed-dependent laws are taken.
std::vector<double> EnergyLossMeanSpeeds(const SequencePlan& plan, const FitOptions& options) {
  std::vector<double> speeds;
  const auto& measured = plan.measured;
  const int count = internal::EtaBarCount(plan, options);
  for (size_t j = 0; j < measured.energy_loss.size() && static_cast<int>(j) < count; ++j)
    speeds.push_back(
        internal::IncomingSpeedMps(plan, measured.impact_index[j], options.drop.gravity_mps2));
  return speeds;
}

// eta-bar of the law's closed form with `name` = value, averaged over each recording's speeds
// and then over the recordings, as the measured eta-bar is; nothing where the law has no closed
// form or the value is not a valid law.
std::optional<double> ClosedFormEnergyLossMean(const dem::ContactLawConfig& law,
                                               const std::string& name, double value,
                                               const dem::Ball& ball,
                                               const std::vector<std::vector<double>>& speeds) {
  dem::ContactLawConfig at = law;
  at.parameters[name] = value;
  std::optional<dem::ContactLaw> built;
  try {
    built = dem::MakeContactLaw(at);
  } catch (const ConfigError&) {
    return std::nullopt;
  }
  double sum = 0;
  for (const auto& recording : speeds) {
    double recording_sum = 0;
    for (double speed : recording) {
      const auto e = dem::ClosedFormRestitutionOf(*built, ball.MassKg(), ball.RadiusM(), speed);
      if (!e) return std::nullopt;
      recording_sum += 1 - *e * *e;
    }
    sum += recording_sum / static_cast<double>(recording.size());
  }
  return sum / static_cast<double>(speeds.size());
}

// The parameter's value in `range` at which `eta_bar` equals `target`: the first crossing from
// the lower end on a grid of 64 steps (in log space for a log range), refined by bisection; the
// first, because an approximate closed form may turn back beyond its validity (the Ramirez series
// of hertz-viscoelastic rises to e = 1 again at large damping). Nothing without a crossing.
std::optional<double> InvertOverRange(const std::function<std::optional<double>(double)>& eta_bar,
                                      const ParameterRange& range, double target) {
  const auto to_value = [&](double u) {
    return range.log_scale ? range.lower * std::pow(range.upper / range.lower, u)
                           : range.lower + u * (range.upper - range.lower);
  };
  constexpr int kGrid = 64;
  auto previous = eta_bar(to_value(0));
  if (!previous) return std::nullopt;
  for (int k = 1; k <= kGrid; ++k) {
    double a = static_cast<double>(k - 1) / kGrid, b = static_cast<double>(k) / kGrid;
    const auto next = eta_bar(to_value(b));
    if (!next) return std::nullopt;
    if ((*previous - target) * (*next - target) <= 0) {
      const bool rising = *next > *previous;
      for (int i = 0; i < 100 && b - a > 1e-14; ++i) {
        const double middle = (a + b) / 2;
        const auto value = eta_bar(to_value(middle));
        if (!value) return std::nullopt;
        ((*value < target) == rising ? a : b) = middle;
      }
      return to_value((a + b) / 2);
    }
    previous = next;
  }
  return std::nullopt;
}

// d eta_bar / d parameter at value by a central difference inside the range (one-sided at an
// edge), steps of 1e-6 of the range (relative for a log range).
std::optional<double> SlopeAt(const std::function<std::optional<double>(double)>& eta_bar,
                              const ParameterRange& range, double value) {
  const double step = range.log_scale ? value * 1e-6 * std::log(range.upper / range.lower)
                                      : 1e-6 * (range.upper - range.lower);
  const double a = std::max(range.lower, value - step), b = std::min(range.upper, value + step);
  const auto fa = eta_bar(a), fb = eta_bar(b);
  if (!fa || !fb || !(b > a)) return std::nullopt;
  return (*fb - *fa) / (b - a);
}

// The measured eta-bar the check inverts: the mean over the recordings of each one's first-N
// mean, the timing variance of their sum and the impact speeds each was measured at.
struct MeasuredEtaBar {
  double mean = 0;
  double timing_variance = 0;
  int recordings = 0;
  double mean_inverse_count = 0;  // of 1 / (the energy losses each eta-bar averages)
  std::vector<std::vector<double>> speeds;
};

MeasuredEtaBar MeasureEtaBar(const std::vector<SequencePlan>& plans, const FitOptions& options) {
  MeasuredEtaBar measured;
  double sum = 0;
  for (const auto& plan : plans) {
    if (!plan.measured.energy_loss_mean_first_n) continue;
    sum += *plan.measured.energy_loss_mean_first_n;
    measured.timing_variance += std::pow(*plan.measured.energy_loss_mean_first_n_uncertainty, 2);
    measured.speeds.push_back(EnergyLossMeanSpeeds(plan, options));
    measured.mean_inverse_count += 1.0 / internal::EtaBarCount(plan, options);
    ++measured.recordings;
  }
  if (measured.recordings > 0) {
    measured.mean = sum / measured.recordings;
    measured.mean_inverse_count /= measured.recordings;
  }
  return measured;
}

// The closed form at the measurement and at the fit: the value it gives for the measured
// eta-bar, its eta-bar at the fitted value (for the first recording's speeds, the simulated
// one), and its slopes at both. walton-braun keeps the paper's formula and its exact inverse.
struct ClosedFormAt {
  std::optional<double> value, eta_at_fit, slope_at_fit, slope_at_value;

  bool Usable() const {
    return value && eta_at_fit && slope_at_fit && slope_at_value && *slope_at_fit != 0 &&
           *slope_at_value != 0;
  }
};

ClosedFormAt EvaluateClosedForm(
    bool paper, double fitted, double eta,
    const std::function<std::optional<double>(double)>& closed_all,
    const std::function<std::optional<double>(double)>& closed_reference,
    const ParameterRange& range) {
  ClosedFormAt at;
  if (paper) {
    at.value = eta / (2 - eta);
    at.eta_at_fit = 2 * fitted / (1 + fitted);
    at.slope_at_fit = 2 / std::pow(1 + fitted, 2);  // d eta / d gamma of the closed form
    at.slope_at_value = std::pow(2 - eta, 2) / 2;
  } else {
    at.value = InvertOverRange(closed_all, range, eta);
    at.eta_at_fit = closed_reference(fitted);
    at.slope_at_fit = SlopeAt(closed_all, range, fitted);
    if (at.value) at.slope_at_value = SlopeAt(closed_all, range, *at.value);
  }
  return at;
}

// Simulates the reference recording with the chosen step, without drag and on the reference
// path, and converts each difference to the parameter (check's time-step, model and drag errors).
// False where the closed form cannot convert them (it does not reach the simulated eta-bar).
bool MeasureErrorBudget(const FitOptions& options, const dem::ContactLawConfig& law,
                        const SequencePlan& reference, bool paper, double slope_at_fit,
                        const std::function<std::optional<double>(double)>& closed_reference,
                        const ParameterRange& range, AnalyticCheck& check) {
  check.energy_loss_mean_chosen_step = SimulatedEnergyLossMean(options, law, reference, true);
  const double chosen_without_drag = SimulatedEnergyLossMean(options, law, reference, false);
  try {
    check.energy_loss_mean_exact =
        SimulatedEnergyLossMean(options, law, reference, false, dem::Integrator::kExact);
    check.reference_integrator = "exact";
  } catch (const ConfigError&) {
    // No exact path (a nonlinear law): RK4 at eight times the steps, on no fixed grid.
    FitOptions fine = options;
    fine.drop.integrator = dem::Integrator::kRungeKutta4;
    fine.drop.steps_per_contact *= 8;
    if (fine.drop.time_step_s) *fine.drop.time_step_s /= 8;
    fine.drop.fixed_step_grid = false;
    check.energy_loss_mean_exact = SimulatedEnergyLossMean(fine, law, reference, false);
    check.reference_integrator = "rk4";
  }
  if (paper) {
    check.time_step_error = (chosen_without_drag - check.energy_loss_mean_exact) / slope_at_fit;
    check.model_error = (check.energy_loss_mean_exact - check.energy_loss_formula) / slope_at_fit;
    check.drag_error = (check.energy_loss_mean_chosen_step - chosen_without_drag) / slope_at_fit;
    return true;
  }
  // Through the closed form's inverse, not its slope: an approximate closed form (the Ramirez
  // series) can be off by several per cent, where the slope's first order falls short.
  const auto reference_value =
      InvertOverRange(closed_reference, range, check.energy_loss_mean_exact);
  const auto chosen_value = InvertOverRange(closed_reference, range, chosen_without_drag);
  const auto drag_value =
      InvertOverRange(closed_reference, range, check.energy_loss_mean_chosen_step);
  if (!reference_value || !chosen_value || !drag_value) return false;
  check.time_step_error = *chosen_value - *reference_value;
  check.model_error = *reference_value - check.fitted_value;
  check.drag_error = *drag_value - *chosen_value;
  return true;
}

// One sentence: the difference against what explains it, each term named.
std::string Sentence(const AnalyticCheck& check, bool paper, const std::string& law_name,
                     const FitOptions& options) {
  char text[700];
  if (paper) {
    std::snprintf(text, sizeof text,
                  "fitted gamma_n differs from the formula by %.4f, %s the %.4f that time-step "
                  "error (%.4f), gravity during contact (%.4f)%s and the uncertainty of eta-bar "
                  "explain",
                  check.difference, check.warning ? "more than" : "within", check.explained,
                  check.time_step_error, check.model_error,
                  options.drop.drag.enabled
                      ? (", air drag (" + Format("%.4f", check.drag_error) + ")").c_str()
                      : "");
  } else {
    std::snprintf(text, sizeof text,
                  "fitted %s differs from the %s closed form's by %.4g, %s the %.4g that "
                  "time-step error (%.4g), the closed form's model error (%.4g)%s and the "
                  "uncertainty of eta-bar explain",
                  check.parameter.c_str(), law_name.c_str(), check.difference,
                  check.warning ? "more than" : "within", check.explained, check.time_step_error,
                  check.model_error,
                  options.drop.drag.enabled
                      ? (", air drag (" + Format("%.4g", check.drag_error) + ")").c_str()
                      : "");
  }
  return text;
}

// Where the fit and eta-bar disagree, the next step depends on why.
std::string NextStep(const FitOptions& options, MinimizerStop stop, bool paper,
                     const std::string& name) {
  if (options.objective != FitObjective::kMeanEnergyLoss) {
    return ": the " + std::string(ToString(options.objective)) +
           " fit also weights later, slower impacts whose energy loss differs, so " +
           (paper ? std::string("one constant gamma") : "one value of " + name) +
           " does not describe these impacts; fit the first impacts only with "
           "`objective=mean-energy-loss`, or rank speed-dependent laws with `compare_laws`";
  }
  if (!IsConverged(stop)) {
    return ": the optimiser did not converge, so the fit does not reproduce eta-bar; raise "
           "`max_evaluations`";
  }
  return ": the drops do not reproduce eta-bar within the optimiser's reach (a jagged objective, "
         "as on a fixed step grid); raise `global_evaluations` or `steps_per_contact`";
}

}  // namespace

AnalyticCheck MakeCheck(const FitOptions& options, const ParameterMap& map,
                        const dem::ContactLawConfig& law, const std::vector<SequencePlan>& plans,
                        const UncertaintySummary& uncertainty, MinimizerStop stop) {
  AnalyticCheck check;
  const std::string law_name(dem::ToString(law.kind));
  // walton-braun keeps the paper's formula and its exact inverse and slope; gamma_n alone sets
  // its energy loss, whatever else is fitted.
  const auto& names = map.names();
  const auto gamma = std::find(names.begin(), names.end(), "gamma_n");
  const bool paper = law.kind == dem::ContactLawKind::kWaltonBraun && gamma != names.end();
  if (!paper && map.size() != 1) {
    check.message = "the closed-form check inverts one fitted parameter, and " +
                    std::to_string(map.size()) + " are fitted";
    return check;
  }
  const size_t index = paper ? static_cast<size_t>(gamma - names.begin()) : 0;
  const std::string& name = names[index];
  const ParameterRange& range = map.ranges()[index];
  check.parameter = name;
  check.formula = paper ? "eta = 2 gamma / (1 + gamma)"
                        : "the " + law_name + " closed form at the measured impact speeds";
  const MeasuredEtaBar measured = MeasureEtaBar(plans, options);
  if (measured.recordings == 0) {
    check.message = "no recording has " + std::to_string(options.first_n) +
                    " energy losses, so eta-bar is unknown";
    return check;
  }
  const double eta = measured.mean;
  const dem::Ball& ball = options.drop.ball;
  const std::function<std::optional<double>(double)> closed_all = [&](double value) {
    return ClosedFormEnergyLossMean(law, name, value, ball, measured.speeds);
  };
  // The model error compares the closed form with the simulated (first) recording alone.
  const std::vector<std::vector<double>> reference_speeds = {measured.speeds.front()};
  const std::function<std::optional<double>(double)> closed_reference = [&](double value) {
    return ClosedFormEnergyLossMean(law, name, value, ball, reference_speeds);
  };
  const double fitted = law.Get(name);
  const ClosedFormAt closed =
      EvaluateClosedForm(paper, fitted, eta, closed_all, closed_reference, range);
  if (!closed.Usable()) {
    check.message = closed_all(range.lower)
                        ? "the " + law_name + " closed form does not reach the measured eta-bar " +
                              Format("%.4f", eta) + " within the search range of " + name
                        : "the " + law_name + " law has no closed-form restitution";
    return check;
  }
  check.applicable = true;
  check.energy_loss_mean = eta;
  // The uncertainty model's components for the mean of the first N of each recording.
  const double count = measured.recordings;
  const double scatter = std::pow(uncertainty.per_impact_scatter, 2) * measured.mean_inverse_count;
  const double between = std::pow(uncertainty.between_recording_sd, 2);
  check.energy_loss_mean_uncertainty =
      std::sqrt(measured.timing_variance / (count * count) + (scatter + between) / count);
  check.formula_value = *closed.value;
  check.fitted_value = fitted;
  check.difference = fitted - check.formula_value;
  check.energy_loss_formula = *closed.eta_at_fit;
  if (!MeasureErrorBudget(options, law, plans.front(), paper, *closed.slope_at_fit,
                          closed_reference, range, check)) {
    AnalyticCheck refused;
    refused.parameter = name;
    refused.formula = check.formula;
    refused.message = "the " + law_name +
                      " closed form does not reach the simulated eta-bar within the search range "
                      "of " +
                      name;
    return refused;
  }
  const double formula_sigma =
      check.energy_loss_mean_uncertainty / std::abs(*closed.slope_at_value);
  // The optimiser's tolerance: 1e-4 in gamma, 1e-4 of the search range otherwise.
  const double tolerance = paper             ? 1e-4
                           : range.log_scale ? 1e-4 * fitted * std::log(range.upper / range.lower)
                                             : 1e-4 * (range.upper - range.lower);
  check.explained = std::abs(check.time_step_error) + std::abs(check.model_error) +
                    std::abs(check.drag_error) + 2 * formula_sigma + tolerance;
  check.warning = std::abs(check.difference) > check.explained;
  check.message = Sentence(check, paper, law_name, options);
  if (check.warning) check.message += NextStep(options, stop, paper, name);
  return check;
}

}  // namespace bouncecal::calibrate::internal
