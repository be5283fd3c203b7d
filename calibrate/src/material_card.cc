#include "bouncecal/calibrate/material_card.h"

#include <ctime>
#include <fstream>

#include "bouncecal/atomic_file.h"
#include "bouncecal/calibrate/content_hash.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"
#include "bouncecal/version.h"

namespace bouncecal::calibrate {
namespace {

template <typename T>
nlohmann::json Optional(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

template <typename T>
std::optional<T> OptionalFrom(const nlohmann::json& object, const char* key) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  return object[key].get<T>();
}

}  // namespace

std::string UtcTimestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

MaterialCard MakeMaterialCard(const FitSummary& summary, const FitOptions& options,
                              const std::vector<std::filesystem::path>& recordings) {
  MaterialCard card;
  card.law = summary.law;
  card.ball = options.ball;
  card.implied_restitution = summary.implied_restitution;
  card.implied_energy_loss = summary.implied_energy_loss;
  auto& fit = card.fit;
  fit.objective = std::string(ToString(summary.objective));
  fit.first_n = options.first_n;
  fit.residual = summary.residual;
  fit.data_points = summary.data_points;
  fit.evaluations = summary.evaluations;
  fit.stop_reason = std::string(ToString(summary.stop));
  fit.drop_height_m = options.drop_height_m;
  fit.integrator = std::string(dem::ToString(options.integrator));
  fit.time_step_s = options.time_step_s;
  fit.steps_per_contact = options.steps_per_contact;
  fit.fixed_step_grid = options.fixed_step_grid;
  fit.drag = options.drag.enabled;
  fit.confidence_level = options.uncertainty.confidence_level;
  fit.uncertainty_method = summary.uncertainty_method;
  for (const auto& parameter : summary.parameters) {
    if (parameter.confidence_interval)
      fit.confidence_interval[parameter.name] = *parameter.confidence_interval;
  }
  if (summary.check.applicable) {
    fit.energy_loss_mean_measured = summary.check.energy_loss_mean;
    fit.gamma_n_formula = summary.check.gamma_n_formula;
  }
  for (const auto& path : recordings)
    card.recordings.push_back({path.filename().string(), FileContentHash(path)});
  card.tool_version = std::string(Version());
  card.created_utc = UtcTimestamp();
  return card;
}

nlohmann::json ToJson(const MaterialCard& card) {
  nlohmann::json units = nlohmann::json::object();
  for (const auto& spec : dem::ParameterSpecs(card.law.kind))
    units[std::string(spec.name)] = std::string(spec.unit);
  nlohmann::json intervals = nlohmann::json::object();
  for (const auto& [name, interval] : card.fit.confidence_interval)
    intervals[name] = {interval.first, interval.second};
  nlohmann::json recordings = nlohmann::json::array();
  for (const auto& recording : card.recordings)
    recordings.push_back({{"file", recording.file}, {"content_hash", recording.content_hash}});
  const auto& fit = card.fit;
  return {
      {"format", kMaterialCardFormat},
      {"contact_law", dem::ToJson(card.law)},
      {"parameter_units", units},
      {"ball",
       {{"diameter_m", card.ball.diameter_m},
        {"density_kg_per_m3", card.ball.density_kg_per_m3},
        {"mass_kg", card.ball.MassKg()}}},
      {"implied",
       {{"restitution", card.implied_restitution}, {"energy_loss", card.implied_energy_loss}}},
      {"fit",
       {{"objective", fit.objective},
        {"first_n", fit.first_n},
        {"residual", fit.residual},
        {"data_points", fit.data_points},
        {"evaluations", fit.evaluations},
        {"stop_reason", fit.stop_reason},
        {"drop_height_m", Optional(fit.drop_height_m)},
        {"integrator", fit.integrator},
        {"time_step_s", Optional(fit.time_step_s)},
        {"steps_per_contact", Optional(fit.steps_per_contact)},
        {"fixed_step_grid", fit.fixed_step_grid},
        {"drag", fit.drag},
        {"confidence_interval", intervals},
        {"confidence_level", fit.confidence_level},
        {"uncertainty_method", fit.uncertainty_method},
        {"energy_loss_mean_measured", Optional(fit.energy_loss_mean_measured)},
        {"gamma_n_formula", Optional(fit.gamma_n_formula)}}},
      {"recordings", recordings},
      {"tool_version", card.tool_version},
      {"created_utc", card.created_utc},
  };
}

MaterialCard MaterialCardFromJson(const nlohmann::json& object, std::string_view context) {
  const std::string where(context);
  if (!object.is_object() || !object.contains("format") || !object["format"].is_string() ||
      object["format"].get<std::string>() != kMaterialCardFormat) {
    throw InputError(where + ": not a material card (\"format\" must be \"" +
                     std::string(kMaterialCardFormat) + "\"); write one with bouncecal " +
                     "calibrate --card");
  }
  if (!object.contains("contact_law")) {
    throw InputError(where + ": material card has no \"contact_law\" object");
  }
  MaterialCard card;
  card.law = dem::ContactLawConfigFromJson(object["contact_law"], where + ": contact_law");
  try {
    if (object.contains("ball")) {
      const auto& ball = object["ball"];
      card.ball.diameter_m = ball.value("diameter_m", card.ball.diameter_m);
      card.ball.density_kg_per_m3 = ball.value("density_kg_per_m3", card.ball.density_kg_per_m3);
      card.ball.mass_kg = OptionalFrom<double>(ball, "mass_kg");
    }
    if (object.contains("implied")) {
      card.implied_restitution = object["implied"].value("restitution", 0.0);
      card.implied_energy_loss = object["implied"].value("energy_loss", 0.0);
    }
    if (object.contains("fit")) {
      const auto& fit = object["fit"];
      card.fit.objective = fit.value("objective", "");
      card.fit.first_n = fit.value("first_n", 3);
      card.fit.residual = fit.value("residual", 0.0);
      card.fit.data_points = fit.value("data_points", 0);
      card.fit.evaluations = fit.value("evaluations", 0);
      card.fit.stop_reason = fit.value("stop_reason", "");
      card.fit.drop_height_m = OptionalFrom<double>(fit, "drop_height_m");
      card.fit.integrator = fit.value("integrator", "");
      card.fit.time_step_s = OptionalFrom<double>(fit, "time_step_s");
      card.fit.steps_per_contact = OptionalFrom<double>(fit, "steps_per_contact");
      card.fit.fixed_step_grid = fit.value("fixed_step_grid", false);
      card.fit.drag = fit.value("drag", false);
      card.fit.confidence_level = fit.value("confidence_level", 0.95);
      card.fit.uncertainty_method = fit.value("uncertainty_method", "");
      card.fit.energy_loss_mean_measured = OptionalFrom<double>(fit, "energy_loss_mean_measured");
      card.fit.gamma_n_formula = OptionalFrom<double>(fit, "gamma_n_formula");
      if (fit.contains("confidence_interval")) {
        for (const auto& [name, interval] : fit["confidence_interval"].items())
          card.fit.confidence_interval[name] = {interval.at(0).get<double>(),
                                                interval.at(1).get<double>()};
      }
    }
    if (object.contains("recordings")) {
      for (const auto& recording : object["recordings"])
        card.recordings.push_back({recording.at("file").get<std::string>(),
                                   recording.at("content_hash").get<std::string>()});
    }
    card.tool_version = object.value("tool_version", "");
    card.created_utc = object.value("created_utc", "");
  } catch (const nlohmann::json::exception& error) {
    throw InputError(where + ": malformed material card field (" + error.what() + ")");
  }
  if (!(card.ball.diameter_m > 0) || !(card.ball.density_kg_per_m3 > 0) ||
      (card.ball.mass_kg && !(*card.ball.mass_kg > 0))) {
    throw InputError(where + ": ball diameter, density and mass must be positive");
  }
  return card;
}

void WriteMaterialCard(const std::filesystem::path& path, const MaterialCard& card) {
  WriteFileAtomically(path, ToJson(card).dump(2) + "\n");
}

MaterialCard ReadMaterialCard(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) {
    throw InputError("cannot open material card '" + path.string() +
                     "'; check the path (write one with bouncecal calibrate --card)");
  }
  nlohmann::json object;
  try {
    object = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw InputError("material card '" + path.string() + "' is not valid JSON (" + error.what() +
                     ")");
  }
  return MaterialCardFromJson(object, path.string());
}

}  // namespace bouncecal::calibrate
