#include "bouncecal/calibrate/fit_json.h"

#include <cmath>
#include <optional>
#include <string>

#include "bouncecal/dem/contact_law_json.h"

namespace bouncecal::calibrate {
namespace {

nlohmann::json ToJson(const RestitutionAnalysis& analysis) {
  return {{"intervals_s", analysis.intervals_s},
          {"interval_uncertainty_s", analysis.interval_uncertainty_s},
          {"bounce_height_m", analysis.bounce_height_m},
          {"impact_index", analysis.impact_index},
          {"restitution", analysis.restitution},
          {"restitution_uncertainty", analysis.restitution_uncertainty},
          {"energy_loss", analysis.energy_loss},
          {"energy_loss_uncertainty", analysis.energy_loss_uncertainty},
          {"energy_loss_mean_first_n", analysis.energy_loss_mean_first_n
                                           ? nlohmann::json(*analysis.energy_loss_mean_first_n)
                                           : nlohmann::json(nullptr)}};
}

template <typename T>
nlohmann::json Optional(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// JSON has no infinity: known-variance-only intervals state their dof as null.
nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json ToJson(const UncertaintySummary& uncertainty) {
  nlohmann::json recordings = nlohmann::json::array();
  for (const auto& recording : uncertainty.recordings) {
    recordings.push_back({{"source", recording.source},
                          {"impacts_used", recording.impacts_used},
                          {"energy_loss_mean", recording.energy_loss_mean},
                          {"energy_loss_mean_uncertainty", recording.energy_loss_mean_uncertainty},
                          {"energy_loss_scatter", recording.energy_loss_scatter},
                          {"parameter_values", recording.parameter_values}});
  }
  nlohmann::json interval = nullptr;
  if (uncertainty.energy_loss_mean_interval) {
    interval = {uncertainty.energy_loss_mean_interval->first,
                uncertainty.energy_loss_mean_interval->second};
  }
  return {{"available", uncertainty.available},
          {"message", uncertainty.message},
          {"model", uncertainty.model},
          {"confidence_level", uncertainty.confidence_level},
          {"sequences", uncertainty.sequences},
          {"duplicates", uncertainty.duplicates},
          {"impacts_used", uncertainty.impacts_used},
          {"per_impact_scatter", uncertainty.per_impact_scatter},
          {"per_impact_dof", uncertainty.per_impact_dof},
          {"per_impact_estimable", uncertainty.per_impact_estimable},
          {"between_recording_sd", uncertainty.between_recording_sd},
          {"between_dof", uncertainty.between_dof},
          {"variance_shares",
           {{"timing", uncertainty.timing_share},
            {"per_impact_scatter", uncertainty.scatter_share},
            {"between_recordings", uncertainty.between_share},
            {"drop_height", uncertainty.drop_height_share}}},
          {"effective_dof", FiniteOrNull(uncertainty.effective_dof)},
          {"t_quantile", uncertainty.t_quantile},
          {"energy_loss_mean", uncertainty.energy_loss_mean},
          {"energy_loss_mean_uncertainty", uncertainty.energy_loss_mean_uncertainty},
          {"energy_loss_sd_across", Optional(uncertainty.energy_loss_sd_across)},
          {"energy_loss_mean_interval", interval},
          {"recordings", recordings}};
}

nlohmann::json ToJson(const ModelAdequacy& adequacy) {
  return {{"tested", adequacy.tested},
          {"impacts", adequacy.impacts},
          {"speed_range_mps", {adequacy.speed_min_mps, adequacy.speed_max_mps}},
          {"slope_per_ln_speed", adequacy.slope_per_ln_speed},
          {"slope_uncertainty_per_ln_speed", adequacy.slope_uncertainty_per_ln_speed},
          {"change_over_range", adequacy.change_over_range},
          {"trend", adequacy.trend},
          {"message", adequacy.message}};
}

}  // namespace

nlohmann::json ToJson(const FitSummary& summary) {
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json intervals = nlohmann::json::object();
  nlohmann::json fitted = nlohmann::json::array();
  // Every parameter of the law, defaults included, so the result states the full law.
  for (const auto& spec : dem::ParameterSpecs(summary.law.kind))
    parameters[std::string(spec.name)] = summary.law.Get(spec.name);
  for (const auto& parameter : summary.parameters) {
    parameters[parameter.name] = parameter.value;
    if (parameter.confidence_interval) {
      intervals[parameter.name] = {parameter.confidence_interval->first,
                                   parameter.confidence_interval->second};
    }
    fitted.push_back({{"name", parameter.name},
                      {"unit", parameter.unit},
                      {"value", parameter.value},
                      {"range", {parameter.range.lower, parameter.range.upper}},
                      {"log_scale", parameter.range.log_scale},
                      {"at_bound", parameter.at_bound},
                      {"interval_clipped", parameter.interval_clipped},
                      {"standard_error", parameter.standard_error}});
  }
  const auto& check = summary.check;
  nlohmann::json analytic = {{"applicable", check.applicable}, {"message", check.message}};
  if (check.applicable) {
    analytic.update({{"parameter", check.parameter},
                     {"formula", check.formula},
                     {"energy_loss_mean", check.energy_loss_mean},
                     {"energy_loss_mean_uncertainty", check.energy_loss_mean_uncertainty},
                     {"formula_value", check.formula_value},
                     {"fitted_value", check.fitted_value},
                     {"difference", check.difference},
                     {"energy_loss_mean_chosen_step", check.energy_loss_mean_chosen_step},
                     {"energy_loss_mean_exact", check.energy_loss_mean_exact},
                     {"reference_integrator", check.reference_integrator},
                     {"energy_loss_formula", check.energy_loss_formula},
                     {"time_step_error", check.time_step_error},
                     {"model_error", check.model_error},
                     {"drag_error", check.drag_error},
                     {"explained", check.explained},
                     {"warning", check.warning}});
    // The names of the walton-braun-only check, kept for older readers.
    if (check.parameter == "gamma_n") {
      analytic.update({{"gamma_n", check.formula_value},
                       {"gamma_n_fitted", check.fitted_value},
                       {"time_step_gamma_error", check.time_step_error},
                       {"model_gamma_error", check.model_error},
                       {"drag_gamma_error", check.drag_error}});
    } else {
      analytic["gamma_n"] = nullptr;  // as before this law's check was applicable
    }
  } else {
    analytic.update({{"energy_loss_mean", nullptr}, {"gamma_n", nullptr}});
  }
  nlohmann::json sequences = nlohmann::json::array();
  for (const auto& sequence : summary.sequences) {
    sequences.push_back(
        {{"source", sequence.source},
         {"drop_height_m", sequence.drop_height_m ? nlohmann::json(*sequence.drop_height_m)
                                                  : nlohmann::json(nullptr)},
         {"residual", sequence.residual},
         {"first_n", sequence.first_n},
         {"measured", ToJson(sequence.measured)},
         {"simulated_onsets_s", sequence.simulated_onsets_s},
         {"simulated", ToJson(sequence.simulated)}});
  }
  return {{"format", kFitFormat},
          {"law", dem::ToString(summary.law.kind)},
          {"contact_law", dem::ToJson(summary.law)},
          {"parameters", parameters},
          {"fitted_parameters", fitted},
          {"confidence_interval", intervals},
          {"uncertainty", ToJson(summary.uncertainty)},
          {"model_adequacy", ToJson(summary.adequacy)},
          {"ball_given", summary.ball_given},
          {"warnings", summary.warnings},
          {"analytic", analytic},
          {"objective", ToString(summary.objective)},
          {"first_n", summary.first_n},
          {"residual", summary.residual},
          {"data_points", summary.data_points},
          {"degrees_of_freedom", summary.degrees_of_freedom},
          {"reduced_chi_square", summary.reduced_chi_square},
          {"aic", summary.aic},
          {"bic", summary.bic},
          {"evaluations", summary.evaluations},
          {"stop_reason", ToString(summary.stop)},
          {"stop_message", summary.stop_message},
          {"implied",
           {{"restitution", summary.implied_restitution},
            {"energy_loss", summary.implied_energy_loss},
            {"contact_duration_s", summary.contact_duration_s
                                       ? nlohmann::json(*summary.contact_duration_s)
                                       : nlohmann::json(nullptr)},
            {"contact_speed_mps", summary.contact_speed_mps}}},
          {"sequences", sequences}};
}

nlohmann::json ToJson(const LawComparison& comparison) {
  nlohmann::json ranking = nlohmann::json::array();
  for (const auto& fit : comparison.fits) {
    auto entry = ToJson(fit);
    entry.erase("format");  // one format field, on the document
    entry["delta_bic"] = fit.bic - comparison.fits.front().bic;
    ranking.push_back(std::move(entry));
  }
  return {{"format", kLawComparisonFormat},
          {"ranking", ranking},
          {"criterion", "bic"},
          {"objective_note", comparison.objective_note.empty()
                                 ? nlohmann::json(nullptr)
                                 : nlohmann::json(comparison.objective_note)},
          {"warnings", comparison.warnings}};
}

}  // namespace bouncecal::calibrate
