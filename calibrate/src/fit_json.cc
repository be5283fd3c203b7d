#include "bouncecal/calibrate/fit_json.h"

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
                      {"bootstrap_std", parameter.bootstrap_std}});
  }
  const auto& check = summary.check;
  nlohmann::json analytic = {{"applicable", check.applicable}, {"message", check.message}};
  if (check.applicable) {
    analytic.update({{"energy_loss_mean", check.energy_loss_mean},
                     {"energy_loss_mean_uncertainty", check.energy_loss_mean_uncertainty},
                     {"gamma_n", check.gamma_n_formula},
                     {"gamma_n_fitted", check.gamma_n_fitted},
                     {"difference", check.difference},
                     {"energy_loss_mean_chosen_step", check.energy_loss_mean_chosen_step},
                     {"energy_loss_mean_exact", check.energy_loss_mean_exact},
                     {"energy_loss_formula", check.energy_loss_formula},
                     {"time_step_gamma_error", check.time_step_gamma_error},
                     {"model_gamma_error", check.model_gamma_error},
                     {"explained", check.explained},
                     {"warning", check.warning}});
  } else {
    analytic.update({{"energy_loss_mean", nullptr}, {"gamma_n", nullptr}});
  }
  nlohmann::json sequences = nlohmann::json::array();
  for (const auto& sequence : summary.sequences) {
    sequences.push_back({{"source", sequence.source},
                         {"residual", sequence.residual},
                         {"measured", ToJson(sequence.measured)},
                         {"simulated_onsets_s", sequence.simulated_onsets_s},
                         {"simulated", ToJson(sequence.simulated)}});
  }
  return {{"law", dem::ToString(summary.law.kind)},
          {"contact_law", dem::ToJson(summary.law)},
          {"parameters", parameters},
          {"fitted_parameters", fitted},
          {"confidence_interval", intervals},
          {"uncertainty_method", summary.uncertainty_method},
          {"bootstrap_samples_used", summary.bootstrap_samples_used},
          {"bootstrap_failures", summary.bootstrap_failures},
          {"analytic", analytic},
          {"objective", ToString(summary.objective)},
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
            {"energy_loss", summary.implied_energy_loss}}},
          {"sequences", sequences}};
}

nlohmann::json ToJson(const LawComparison& comparison) {
  nlohmann::json ranking = nlohmann::json::array();
  for (const auto& fit : comparison.fits) {
    auto entry = ToJson(fit);
    entry["delta_bic"] = fit.bic - comparison.fits.front().bic;
    ranking.push_back(std::move(entry));
  }
  return {{"ranking", ranking}, {"criterion", "bic"}};
}

}  // namespace bouncecal::calibrate
