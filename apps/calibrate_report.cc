#include "calibrate_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "bouncecal/calibrate/contact_stiffness.h"
#include "option_names.h"

namespace bouncecal::apps {
namespace {

std::string FormatValue(double value) { return fmt::format("{:.6g}", value); }

std::string FixedParameters(const calibrate::FitSummary& summary) {
  std::string text;
  for (const auto& spec : dem::ParameterSpecs(summary.law.kind)) {
    const bool fitted = std::any_of(summary.parameters.begin(), summary.parameters.end(),
                                    [&](const auto& p) { return p.name == spec.name; });
    if (!fitted) {
      text += fmt::format("{}{} = {} {}", text.empty() ? "fixed: " : ", ", spec.name,
                          FormatValue(summary.law.Get(spec.name)), spec.unit);
    }
  }
  return text.empty() ? "no fixed parameters" : text;
}

void PrintParameters(std::FILE* out, const calibrate::FitSummary& summary,
                     double confidence_level) {
  for (const auto& parameter : summary.parameters) {
    std::string interval = "no interval (" + WithFlags(summary.uncertainty.message) + ")";
    if (parameter.confidence_interval) {
      interval = fmt::format("{:.0f} % CI [{}, {}]{}", 100 * confidence_level,
                             FormatValue(parameter.confidence_interval->first),
                             FormatValue(parameter.confidence_interval->second),
                             parameter.interval_clipped ? " (cut at the search range)" : "");
    }
    fmt::print(out, "  {} = {} {}   {}{}\n", parameter.name, FormatValue(parameter.value),
               parameter.unit == "1" ? "" : parameter.unit, interval,
               parameter.at_bound ? "   (at the edge of its search range)" : "");
  }
}

std::string BallLine(const calibrate::FitSummary& summary, const calibrate::FitOptions& options) {
  if (!options.ball_given) {
    return fmt::format(
        "ball: not given ({} loses the same fraction of energy whatever the ball, so the drops "
        "simulate the 1 cm steel reference; give --ball for a card)",
        dem::ToString(summary.law.kind));
  }
  return fmt::format("ball: {}d = {} m, m = {:.4g} kg",
                     options.ball_preset.empty() ? "" : options.ball_preset + ", ",
                     FormatValue(options.drop.ball.diameter_m), options.drop.ball.MassKg());
}

std::string DropHeightLine(const calibrate::FitSummary& summary,
                           const calibrate::FitOptions& options) {
  if (const auto height = options.GivenDropHeightM())
    return "drop height " + FormatValue(*height) + " m";
  std::string heights;
  for (const auto& sequence : summary.sequences) {
    heights += (heights.empty() ? "" : ", ") + sequence.source + " " +
               (sequence.drop_height_m ? FormatValue(*sequence.drop_height_m) + " m"
                                       : std::string("not given"));
  }
  const bool any_height =
      std::any_of(summary.sequences.begin(), summary.sequences.end(),
                  [](const auto& sequence) { return sequence.drop_height_m.has_value(); });
  if (any_height) return "drop heights per recording: " + heights;
  std::string apexes;
  for (const auto& sequence : summary.sequences) {
    if (sequence.measured.bounce_height_m.empty()) continue;
    apexes += (apexes.empty() ? "" : ", ") +
              fmt::format("{:.3g}", sequence.measured.bounce_height_m.front());
  }
  return "drop height not given: e_1 and eta_1 are not computed and the drops start from the "
         "first measured bounce apex (" +
         apexes + " m)";
}

void PrintAcrossRecordings(std::FILE* out, const calibrate::FitSummary& summary,
                           double confidence_level) {
  const auto& uncertainty = summary.uncertainty;
  if (uncertainty.recordings.size() < 2 || !uncertainty.energy_loss_sd_across) return;
  std::string per_recording;
  for (const auto& recording : uncertainty.recordings) {
    if (recording.parameter_values.empty()) continue;
    per_recording +=
        (per_recording.empty() ? "" : ", ") + FormatValue(recording.parameter_values.front());
  }
  fmt::print(
      out,
      "  across {} recordings: eta-bar = {:.4f} +- {:.2g} (sd), {:.0f} % interval of the mean "
      "[{:.4f}, {:.4f}]{}\n",
      uncertainty.recordings.size(), uncertainty.energy_loss_mean,
      *uncertainty.energy_loss_sd_across, 100 * confidence_level,
      uncertainty.energy_loss_mean_interval->first, uncertainty.energy_loss_mean_interval->second,
      per_recording.empty() || summary.parameters.empty()
          ? ""
          : "; " + summary.parameters.front().name + " of each alone: " + per_recording);
}

}  // namespace

void PrintFit(std::FILE* out, const calibrate::FitSummary& summary,
              const calibrate::FitOptions& options, size_t sequence_count) {
  fmt::print(out, "bouncecal calibrate: {} sequence(s), law {}, objective {}{}\n", sequence_count,
             dem::ToString(summary.law.kind), ToString(summary.objective),
             summary.objective == calibrate::FitObjective::kMeanEnergyLoss
                 ? fmt::format(" (first {} impacts)", summary.first_n)
                 : "");
  fmt::print(out, "{}\n{}; integrator {}{}\n", BallLine(summary, options),
             DropHeightLine(summary, options), dem::ToString(options.drop.integrator),
             options.drop.drag.enabled ? ", air drag on" : "");
  if (summary.contact_duration_s) {
    // The stiffness is not fitted; say what it means, since it sets the step of every run.
    const std::string elastic(calibrate::ElasticParameterName(summary.law.kind));
    const auto specs = dem::ParameterSpecs(summary.law.kind);
    const auto spec = std::find_if(specs.begin(), specs.end(),
                                   [&](const dem::ParameterSpec& c) { return c.name == elastic; });
    fmt::print(out,
               "contact: {} = {:.4g} {} ({}) lasts {:.4g} s for this ball at {:.3g} m/s "
               "(closed form); it sets the DEM time step, not the damping\n",
               elastic, summary.law.Get(elastic), spec->unit,
               options.drop.law.parameters.contains(elastic) ? "given" : "the law's default",
               *summary.contact_duration_s, summary.contact_speed_mps);
  }
  const double scatter = summary.uncertainty.per_impact_scatter;
  for (size_t r = 0; r < summary.sequences.size(); ++r) {
    const auto& measured = summary.sequences[r].measured;
    const int first_n =
        summary.sequences[r].first_n > 0 ? summary.sequences[r].first_n : summary.first_n;
    std::string eta_bar = "n/a";
    if (measured.energy_loss_mean_first_n) {
      // Scatter and timing, as the uncertainty model combines them for the first N.
      const double timing = *measured.energy_loss_mean_first_n_uncertainty;
      eta_bar = fmt::format("{:.4f} +- {:.2g} (timing alone +- {:.2g})",
                            *measured.energy_loss_mean_first_n,
                            std::sqrt(scatter * scatter / first_n + timing * timing), timing);
    }
    std::string spread;
    if (r < summary.uncertainty.recordings.size() &&
        summary.uncertainty.recordings[r].impacts_used >= 2) {
      const auto& recording = summary.uncertainty.recordings[r];
      spread = fmt::format("; eta_k about the law: sd {:.2g} over {} fitted impacts",
                           recording.energy_loss_scatter, recording.impacts_used);
    }
    fmt::print(out, "  {}: {} impacts, eta-bar(first {}) = {}{}\n", summary.sequences[r].source,
               measured.intervals_s.size() + 1, first_n, eta_bar, spread);
  }
  fmt::print(out, "fitted parameters ({}):\n", FixedParameters(summary));
  PrintParameters(out, summary, options.uncertainty.confidence_level);
  fmt::print(out, "  uncertainty: {}\n", WithFlags(summary.uncertainty.model));
  PrintAcrossRecordings(out, summary, options.uncertainty.confidence_level);
  fmt::print(out, "  model adequacy: {}\n", WithFlags(summary.adequacy.message));
  fmt::print(out, "  implied first impact: e = {:.4f}, eta = {:.4f}\n", summary.implied_restitution,
             summary.implied_energy_loss);
  const auto& check = summary.check;
  if (check.applicable && check.parameter == "gamma_n") {
    fmt::print(out, "analytic check (eta = 2 gamma / (1 + gamma)):\n");
    fmt::print(out, "  measured eta-bar = {:.4f} +- {:.2g} -> gamma_n = eta/(2 - eta) = {:.4f}\n",
               check.energy_loss_mean, check.energy_loss_mean_uncertainty, check.formula_value);
    fmt::print(
        out,
        "  fitted - formula = {:+.4f}; time-step error {:+.4f} (eta-bar {:.4f} with this "
        "step vs {:.4f} exact), gravity during contact {:+.4f}{}\n",
        check.difference, check.time_step_error, check.energy_loss_mean_chosen_step,
        check.energy_loss_mean_exact, check.model_error,
        options.drop.drag.enabled ? fmt::format(", air drag {:+.4f}", check.drag_error) : "");
    fmt::print(out, "  {}\n", WithFlags(check.message));
  } else if (check.applicable) {
    fmt::print(out, "analytic check ({}):\n", check.formula);
    fmt::print(out, "  measured eta-bar = {:.4f} +- {:.2g} -> {} = {:.6g}\n",
               check.energy_loss_mean, check.energy_loss_mean_uncertainty, check.parameter,
               check.formula_value);
    fmt::print(
        out,
        "  fitted - closed form = {:+.4g}; time-step error {:+.4g} (eta-bar {:.4f} with this "
        "step vs {:.4f} {}), closed-form model error {:+.4g}{}\n",
        check.difference, check.time_step_error, check.energy_loss_mean_chosen_step,
        check.energy_loss_mean_exact, check.reference_integrator, check.model_error,
        options.drop.drag.enabled ? fmt::format(", air drag {:+.4g}", check.drag_error) : "");
    fmt::print(out, "  {}\n", WithFlags(check.message));
  } else {
    fmt::print(out, "analytic check: not applicable ({})\n", WithFlags(check.message));
  }
  fmt::print(out,
             "optimiser: stopped because {} ({}); {} evaluations; residual chi^2 = {:.4g} over "
             "{} data ({} dof); fit {:.3f} s, total {:.3f} s\n",
             WithFlags(summary.stop_message), ToString(summary.stop), summary.evaluations,
             summary.residual, summary.data_points, summary.degrees_of_freedom, summary.fit_time_s,
             summary.total_time_s);
  for (const auto& warning : summary.warnings) fmt::print(out, "WARNING: {}\n", WithFlags(warning));
}

void PrintComparison(std::FILE* out, const calibrate::LawComparison& comparison,
                     size_t sequence_count) {
  fmt::print(out,
             "bouncecal calibrate --compare-laws: {} sequence(s), objective {}; ranked by BIC "
             "(chi^2 + k ln n)\n",
             sequence_count, ToString(comparison.fits.front().objective));
  if (!comparison.objective_note.empty())
    fmt::print(out, "  note: {}\n", WithFlags(comparison.objective_note));
  fmt::print(out, "  {:<22} {:>12} {:>5} {:>10} {:>10} {:>10} {:>9}  parameters\n", "law", "chi^2",
             "n", "AIC", "BIC", "dBIC", "dof");
  const double best = comparison.fits.front().bic;
  for (const auto& fit : comparison.fits) {
    std::string parameters;
    for (const auto& parameter : fit.parameters) {
      parameters += fmt::format("{}{} = {}", parameters.empty() ? "" : ", ", parameter.name,
                                FormatValue(parameter.value));
      if (parameter.confidence_interval) {
        parameters += fmt::format(" [{}, {}]", FormatValue(parameter.confidence_interval->first),
                                  FormatValue(parameter.confidence_interval->second));
      } else {
        parameters += " (no interval)";
      }
    }
    fmt::print(out, "  {:<22} {:>12.5g} {:>5} {:>10.4g} {:>10.4g} {:>10.3g} {:>9}  {}\n",
               dem::ToString(fit.law.kind), fit.residual, fit.data_points, fit.aic, fit.bic,
               fit.bic - best, fit.degrees_of_freedom, parameters);
  }
  fmt::print(out, "  dBIC > 10 is very strong evidence against a law (Kass & Raftery 1995)\n");
  const auto& winner = comparison.fits.front();
  fmt::print(out, "  model adequacy of {}: {}\n", dem::ToString(winner.law.kind),
             WithFlags(winner.adequacy.message));
  for (const auto& warning : winner.warnings) fmt::print(out, "WARNING: {}\n", WithFlags(warning));
  for (const auto& warning : comparison.warnings)
    fmt::print(out, "WARNING: {}\n", WithFlags(warning));
}

std::vector<PlotPanel> FitPlotPanels(const calibrate::FitSummary& summary) {
  PlotPanel energy{
      "Energy loss per impact: measured vs fitted " + std::string(dem::ToString(summary.law.kind)),
      "impact number k",
      "energy loss eta_k (1)",
      {},
      {},
      {},
      false,
      "outside right top vertical"};
  PlotPanel flights{
      "Flight time between impacts", "interval number k", "flight time dt_k (s)", {}, {}, {}, true,
      "outside right top vertical"};
  const size_t shown = std::min<size_t>(summary.sequences.size(), 4);
  for (size_t s = 0; s < shown; ++s) {
    const auto& sequence = summary.sequences[s];
    PlotSeries measured{
        sequence.source + " measured (1 sigma)", {}, {}, {}, SeriesStyle::kErrorBars, false};
    for (size_t j = 0; j < sequence.measured.energy_loss.size(); ++j) {
      measured.x.push_back(sequence.measured.impact_index[j] + 1);
      measured.y.push_back(sequence.measured.energy_loss[j]);
      measured.y_error.push_back(sequence.measured.energy_loss_uncertainty[j]);
    }
    PlotSeries simulated{sequence.source + " fitted drop", {},  {}, {},
                         SeriesStyle::kLinesPoints,        true};
    for (size_t j = 0; j < sequence.simulated.energy_loss.size(); ++j) {
      simulated.x.push_back(sequence.simulated.impact_index[j] + 1);
      simulated.y.push_back(sequence.simulated.energy_loss[j]);
    }
    if (!measured.x.empty()) energy.series.push_back(measured);
    if (!simulated.x.empty()) energy.series.push_back(simulated);

    PlotSeries measured_flights{sequence.source + " measured", {},   {}, {},
                                SeriesStyle::kErrorBars,       false};
    for (size_t j = 0; j < sequence.measured.intervals_s.size(); ++j) {
      measured_flights.x.push_back(static_cast<double>(j + 1));
      measured_flights.y.push_back(sequence.measured.intervals_s[j]);
      measured_flights.y_error.push_back(sequence.measured.interval_uncertainty_s[j]);
    }
    PlotSeries simulated_flights{sequence.source + " fitted drop", {},  {}, {},
                                 SeriesStyle::kLinesPoints,        true};
    // The simulation starts at the measured impact it stands for (1 with an unknown height).
    const int offset = sequence.drop_height_m ? 0 : 1;
    for (size_t j = 0; j + 1 < sequence.simulated_onsets_s.size(); ++j) {
      simulated_flights.x.push_back(static_cast<double>(j + 1 + offset));
      simulated_flights.y.push_back(sequence.simulated_onsets_s[j + 1] -
                                    sequence.simulated_onsets_s[j]);
    }
    flights.series.push_back(measured_flights);
    if (!simulated_flights.x.empty()) flights.series.push_back(simulated_flights);
  }
  if (summary.check.applicable) {
    const double x_max = energy.series.empty() || energy.series.front().x.empty()
                             ? 3.0
                             : energy.series.front().x.back();
    energy.series.push_back({summary.check.parameter == "gamma_n"
                                 ? "formula 2 gamma/(1+gamma) at the fitted gamma_n"
                                 : "closed form at the fitted " + summary.check.parameter,
                             {1.0, x_max},
                             {summary.check.energy_loss_formula, summary.check.energy_loss_formula},
                             {},
                             SeriesStyle::kLines,
                             false});
  }
  double last = 1;
  for (const auto& series : flights.series) {
    if (!series.x.empty()) last = std::max(last, series.x.back());
  }
  energy.x_range = flights.x_range = std::make_pair(0.0, last + 1);
  energy.integer_x = flights.integer_x = true;
  // A log axis only helps across a decade; within one it shows a single labelled tick.
  double shortest = 1e300, longest = 0;
  for (const auto& series : flights.series) {
    for (double y : series.y) {
      if (y > 0) shortest = std::min(shortest, y);
      longest = std::max(longest, y);
    }
  }
  flights.log_y = longest > 10 * shortest;
  return {energy, flights};
}

void PlotFit(const std::filesystem::path& target, const calibrate::FitSummary& summary) {
  RenderPlot(target, FitPlotPanels(summary));
}

std::optional<PlotPanel> GammaEtaPanel(const calibrate::FitSummary& summary) {
  const auto& check = summary.check;
  // The curve is walton-braun's; other laws' closed forms depend on more than their parameter.
  if (!check.applicable || check.parameter != "gamma_n") return std::nullopt;
  PlotPanel panel;
  panel.title = "Analytic check: energy loss vs damping, eta = 2 gamma_n / (1 + gamma_n)";
  panel.x_label = "damping gamma_n (1)";
  panel.y_label = "energy loss eta (1)";
  panel.legend_position = "bottom right";
  PlotSeries curve;
  curve.title = "eta = 2 gamma_n / (1 + gamma_n) (Walton & Braun 1986)";
  constexpr int kCurvePoints = 101;
  for (int i = 0; i < kCurvePoints; ++i) {
    const double gamma = static_cast<double>(i) / (kCurvePoints - 1);
    curve.x.push_back(gamma);
    curve.y.push_back(2 * gamma / (1 + gamma));
  }
  panel.series.push_back(std::move(curve));
  PlotSeries measured;
  measured.title = "measured eta-bar (1 sigma) at the formula's gamma_n";
  measured.style = SeriesStyle::kErrorBars;
  measured.x = {check.formula_value};
  measured.y = {check.energy_loss_mean};
  measured.y_error = {check.energy_loss_mean_uncertainty};
  panel.series.push_back(std::move(measured));
  PlotSeries fitted;
  fitted.title = "DEM fit: gamma_n fitted, eta-bar simulated with the chosen step";
  fitted.style = SeriesStyle::kPoints;
  fitted.point_type = 9;
  fitted.point_size = 1.6;
  fitted.x = {check.fitted_value};
  fitted.y = {check.energy_loss_mean_chosen_step};
  panel.series.push_back(std::move(fitted));
  panel.x_range = std::make_pair(0.0, 1.0);
  panel.y_range = std::make_pair(0.0, 1.0);
  return panel;
}

}  // namespace bouncecal::apps
