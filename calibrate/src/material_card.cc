#include "bouncecal/calibrate/material_card.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>

#include "bouncecal/atomic_file.h"
#include "bouncecal/calibrate/content_hash.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "bouncecal/version.h"

namespace bouncecal::calibrate {
namespace {

template <typename T>
nlohmann::json Optional(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// Card readers name the offending key in every error: a card is typed or edited by hand, and
// "type must be number, but is string" alone does not say where to look.
void RejectUnknownKeys(const nlohmann::json& object, const std::string& where,
                       std::initializer_list<std::string_view> known) {
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string list;
      for (const auto name : known) list += (list.empty() ? "" : ", ") + std::string(name);
      throw InputError(where + ": unknown key \"" + key + "\" (valid keys: " + list + ")");
    }
  }
}

bool IsFiniteNumber(const nlohmann::json& value) {
  return value.is_number() && std::isfinite(value.get<double>());
}

const nlohmann::json& ObjectAt(const nlohmann::json& object, const char* key,
                               const std::string& where) {
  const auto& value = object[key];
  if (!value.is_object()) {
    throw InputError(where + ": \"" + key + "\" must be an object, not " +
                     std::string(value.type_name()));
  }
  return value;
}

// Absent or null gives nothing; anything but the expected type is an InputError naming the key.
std::optional<double> NumberAt(const nlohmann::json& object, const char* key,
                               const std::string& where) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  if (!IsFiniteNumber(object[key])) {
    throw InputError(where + ": \"" + key + "\" must be a finite number, not " +
                     object[key].dump());
  }
  return object[key].get<double>();
}

std::optional<int> IntegerAt(const nlohmann::json& object, const char* key,
                             const std::string& where) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  const auto& value = object[key];
  if (!value.is_number_integer() || value.get<std::int64_t>() < 0 ||
      value.get<std::int64_t>() > std::numeric_limits<int>::max()) {
    throw InputError(where + ": \"" + key + "\" must be a non-negative integer, not " +
                     value.dump());
  }
  return static_cast<int>(value.get<std::int64_t>());
}

std::optional<std::string> StringAt(const nlohmann::json& object, const char* key,
                                    const std::string& where) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  if (!object[key].is_string()) {
    throw InputError(where + ": \"" + key + "\" must be a string, not " + object[key].dump());
  }
  return object[key].get<std::string>();
}

std::optional<bool> BoolAt(const nlohmann::json& object, const char* key,
                           const std::string& where) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  if (!object[key].is_boolean()) {
    throw InputError(where + ": \"" + key + "\" must be true or false, not " + object[key].dump());
  }
  return object[key].get<bool>();
}

}  // namespace

std::string UtcTimestamp(std::time_t seconds_since_epoch) {
  std::tm utc{};
  gmtime_r(&seconds_since_epoch, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

void CheckCardOptions(const FitOptions& options) {
  if (!options.ball_given) {
    throw OptionError(
        {"ball", "diameter_m", "density_kg_per_m3", "mass_kg"},
        "a material card records the ball its damping was calibrated with (exported damping "
        "scales with its mass); give `ball` NAME or diameter_m with density_kg_per_m3 or mass_kg");
  }
}

MaterialCard MakeMaterialCard(const FitSummary& summary, const FitOptions& options,
                              const std::vector<std::filesystem::path>& recordings,
                              std::time_t created_at) {
  CheckCardOptions(options);
  MaterialCard card;
  card.law = summary.law;
  card.ball = options.drop.ball;
  card.ball_preset = options.ball_preset;
  card.implied_restitution = summary.implied_restitution;
  card.implied_energy_loss = summary.implied_energy_loss;
  card.implied_contact_duration_s = summary.contact_duration_s;
  if (summary.contact_speed_mps > 0) card.implied_contact_speed_mps = summary.contact_speed_mps;
  auto& fit = card.fit;
  fit.objective = std::string(ToString(summary.objective));
  fit.first_n = summary.first_n;
  fit.residual = summary.residual;
  fit.data_points = summary.data_points;
  fit.evaluations = summary.evaluations;
  fit.stop_reason = std::string(ToString(summary.stop));
  const dem::DropOptions& drop = options.drop;
  fit.drop_height_m = options.GivenDropHeightM();
  fit.integrator = std::string(dem::ToString(drop.integrator));
  fit.time_step_s = drop.time_step_s;
  // null: the drop engine's default accuracy, as the card has always written it.
  if (drop.steps_per_contact != dem::DropOptions{}.steps_per_contact)
    fit.steps_per_contact = drop.steps_per_contact;
  fit.fixed_step_grid = drop.fixed_step_grid;
  fit.drag = drop.drag.enabled;
  fit.confidence_level = options.uncertainty.confidence_level;
  fit.uncertainty_method = summary.uncertainty.model;
  const auto& uncertainty = summary.uncertainty;
  fit.uncertainty.model = uncertainty.model;
  fit.uncertainty.sequences = uncertainty.sequences;
  fit.uncertainty.duplicates = uncertainty.duplicates;
  fit.uncertainty.impacts_used = uncertainty.impacts_used;
  fit.uncertainty.per_impact_scatter = uncertainty.per_impact_scatter;
  fit.uncertainty.between_recording_sd = uncertainty.between_recording_sd;
  if (uncertainty.available && std::isfinite(uncertainty.effective_dof))
    fit.uncertainty.effective_dof = uncertainty.effective_dof;
  for (const auto& parameter : summary.parameters) {
    if (parameter.confidence_interval)
      fit.confidence_interval[parameter.name] = *parameter.confidence_interval;
  }
  if (summary.check.applicable) {
    fit.energy_loss_mean_measured = summary.check.energy_loss_mean;
    if (summary.check.parameter == "gamma_n") fit.gamma_n_formula = summary.check.formula_value;
  }
  // One height for all, or each recording its own (FitOptions' height, or the sequences').
  std::vector<std::optional<double>> heights;
  for (const auto& sequence : summary.sequences) heights.push_back(sequence.drop_height_m);
  const bool one_height =
      std::adjacent_find(heights.begin(), heights.end(), std::not_equal_to<>()) == heights.end();
  if (!fit.drop_height_m && !heights.empty() && heights.front()) {
    if (one_height) {
      fit.drop_height_m = heights.front();
    } else {
      fit.heights_per_recording = true;
    }
  }
  for (const auto& path : recordings) {
    RecordingReference reference{path.filename().string(), FileContentHash(path), std::nullopt,
                                 std::nullopt};
    for (const auto& sequence : summary.sequences) {
      if (sequence.path != path) continue;
      if (sequence.drop_height_m && !reference.drop_height_m) {
        reference.drop_height_m = sequence.drop_height_m;
      }
      if (sequence.first_n > 0) {
        reference.first_n =
            std::min(reference.first_n.value_or(sequence.first_n), sequence.first_n);
      }
    }
    if (!reference.drop_height_m) reference.drop_height_m = options.GivenDropHeightM();
    const bool listed = std::any_of(card.recordings.begin(), card.recordings.end(),
                                    [&](const RecordingReference& other) {
                                      return other.content_hash == reference.content_hash;
                                    });
    if (!listed) card.recordings.push_back(std::move(reference));
  }
  fit.uncertainty.recordings = static_cast<int>(card.recordings.size());
  card.tool_version = std::string(Version());
  card.created_utc = UtcTimestamp(created_at);
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
    recordings.push_back(
        {{"file", recording.file},
         {"content_hash", recording.content_hash},
         {"drop_height_m", Optional(recording.drop_height_m)},
         {"first_n", recording.first_n ? nlohmann::json(*recording.first_n) : nlohmann::json()}});
  const auto& fit = card.fit;
  nlohmann::json ball = {{"diameter_m", card.ball.diameter_m},
                         {"density_kg_per_m3", card.ball.DensityKgPerM3()},
                         {"mass_kg", card.ball.MassKg()}};
  if (!card.ball_preset.empty()) ball["preset"] = card.ball_preset;
  const auto& uncertainty = fit.uncertainty;
  return {
      {"format", kMaterialCardFormat},
      {"contact_law", dem::ToJson(card.law)},
      {"parameter_units", units},
      {"ball", ball},
      {"implied",
       {{"restitution", card.implied_restitution},
        {"energy_loss", card.implied_energy_loss},
        {"contact_duration_s", Optional(card.implied_contact_duration_s)},
        {"contact_speed_mps", Optional(card.implied_contact_speed_mps)}}},
      {"fit",
       {{"objective", fit.objective},
        {"first_n", fit.first_n},
        {"residual", fit.residual},
        {"data_points", fit.data_points},
        {"evaluations", fit.evaluations},
        {"stop_reason", fit.stop_reason},
        {"drop_height_m", Optional(fit.drop_height_m)},
        {"release", fit.drop_height_m           ? "drop-height"
                    : fit.heights_per_recording ? "per-recording"
                                                : "first-bounce-apex"},
        {"integrator", fit.integrator},
        {"time_step_s", Optional(fit.time_step_s)},
        {"steps_per_contact", Optional(fit.steps_per_contact)},
        {"fixed_step_grid", fit.fixed_step_grid},
        {"drag", fit.drag},
        {"confidence_interval", intervals},
        {"confidence_level", fit.confidence_level},
        {"uncertainty_method", fit.uncertainty_method},
        {"uncertainty",
         {{"model", uncertainty.model},
          {"recordings", uncertainty.recordings},
          {"sequences", uncertainty.sequences},
          {"duplicates", uncertainty.duplicates},
          {"impacts_used", uncertainty.impacts_used},
          {"per_impact_scatter", uncertainty.per_impact_scatter},
          {"between_recording_sd", uncertainty.between_recording_sd},
          {"effective_dof", Optional(uncertainty.effective_dof)}}},
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
                     std::string(kMaterialCardFormat) + "\"); calibrate writes one: `card`");
  }
  RejectUnknownKeys(object, where,
                    {"format", "contact_law", "parameter_units", "ball", "implied", "fit",
                     "recordings", "tool_version", "created_utc"});
  if (!object.contains("contact_law")) {
    throw InputError(where + ": material card has no \"contact_law\" object");
  }
  MaterialCard card;
  card.law = dem::ContactLawConfigFromJson(object["contact_law"], where + ": contact_law");
  if (object.contains("ball")) {
    const auto& ball = ObjectAt(object, "ball", where);
    const std::string at = where + ": ball";
    RejectUnknownKeys(ball, at, {"diameter_m", "density_kg_per_m3", "mass_kg", "preset"});
    card.ball_preset = StringAt(ball, "preset", at).value_or("");
    card.ball.diameter_m = NumberAt(ball, "diameter_m", at).value_or(card.ball.diameter_m);
    card.ball.density_kg_per_m3 =
        NumberAt(ball, "density_kg_per_m3", at).value_or(card.ball.density_kg_per_m3);
    card.ball.mass_kg = NumberAt(ball, "mass_kg", at);
  }
  // The mass is what the drops feel. Cards written before the ball reported its own density carry
  // steel's 7800 kg/m^3 beside a hollow ball's mass; the mass wins (dem::Ball's rule), and the
  // card read back states the density that mass implies.
  if (card.ball.mass_kg && *card.ball.mass_kg > 0 && card.ball.diameter_m > 0)
    card.ball.density_kg_per_m3 = card.ball.DensityKgPerM3();
  if (!(card.ball.diameter_m > 0) || !(card.ball.density_kg_per_m3 > 0) ||
      (card.ball.mass_kg && !(*card.ball.mass_kg > 0))) {
    throw InputError(where + ": ball diameter_m, density_kg_per_m3 and mass_kg must be positive");
  }
  if (object.contains("implied")) {
    const auto& implied = ObjectAt(object, "implied", where);
    const std::string at = where + ": implied";
    RejectUnknownKeys(implied, at,
                      {"restitution", "energy_loss", "contact_duration_s", "contact_speed_mps"});
    card.implied_restitution = NumberAt(implied, "restitution", at).value_or(0.0);
    card.implied_energy_loss = NumberAt(implied, "energy_loss", at).value_or(0.0);
    card.implied_contact_duration_s = NumberAt(implied, "contact_duration_s", at);
    card.implied_contact_speed_mps = NumberAt(implied, "contact_speed_mps", at);
  }
  if (object.contains("fit")) {
    const auto& fit = ObjectAt(object, "fit", where);
    const std::string at = where + ": fit";
    RejectUnknownKeys(
        fit, at,
        {"objective", "first_n", "residual", "data_points", "evaluations", "stop_reason",
         "drop_height_m", "release", "integrator", "time_step_s", "steps_per_contact",
         "fixed_step_grid", "drag", "confidence_interval", "confidence_level", "uncertainty_method",
         "uncertainty", "energy_loss_mean_measured", "gamma_n_formula"});
    auto& record = card.fit;
    record.objective = StringAt(fit, "objective", at).value_or("");
    record.first_n = IntegerAt(fit, "first_n", at).value_or(3);
    record.residual = NumberAt(fit, "residual", at).value_or(0.0);
    record.data_points = IntegerAt(fit, "data_points", at).value_or(0);
    record.evaluations = IntegerAt(fit, "evaluations", at).value_or(0);
    record.stop_reason = StringAt(fit, "stop_reason", at).value_or("");
    record.drop_height_m = NumberAt(fit, "drop_height_m", at);
    if (const auto release = StringAt(fit, "release", at)) {
      if (*release != "drop-height" && *release != "first-bounce-apex" &&
          *release != "per-recording") {
        throw InputError(at +
                         ": \"release\" must be \"drop-height\", \"per-recording\" or "
                         "\"first-bounce-apex\", not \"" +
                         *release + "\"");
      }
      record.heights_per_recording = *release == "per-recording";
      if ((*release == "drop-height") != record.drop_height_m.has_value()) {
        throw InputError(at + ": \"release\" is \"" + *release + "\" but \"drop_height_m\" is " +
                         (record.drop_height_m ? "given" : "null") + "; make them agree");
      }
    }
    record.integrator = StringAt(fit, "integrator", at).value_or("");
    record.time_step_s = NumberAt(fit, "time_step_s", at);
    record.steps_per_contact = NumberAt(fit, "steps_per_contact", at);
    record.fixed_step_grid = BoolAt(fit, "fixed_step_grid", at).value_or(false);
    record.drag = BoolAt(fit, "drag", at).value_or(false);
    record.confidence_level = NumberAt(fit, "confidence_level", at).value_or(0.95);
    record.uncertainty_method = StringAt(fit, "uncertainty_method", at).value_or("");
    if (fit.contains("uncertainty")) {
      const auto& uncertainty = ObjectAt(fit, "uncertainty", at);
      const std::string where_uncertainty = at + ": uncertainty";
      RejectUnknownKeys(uncertainty, where_uncertainty,
                        {"model", "recordings", "sequences", "duplicates", "impacts_used",
                         "per_impact_scatter", "between_recording_sd", "effective_dof"});
      auto& out = record.uncertainty;
      out.model = StringAt(uncertainty, "model", where_uncertainty).value_or("");
      out.recordings = IntegerAt(uncertainty, "recordings", where_uncertainty).value_or(0);
      out.sequences = IntegerAt(uncertainty, "sequences", where_uncertainty).value_or(0);
      out.duplicates = IntegerAt(uncertainty, "duplicates", where_uncertainty).value_or(0);
      out.impacts_used = IntegerAt(uncertainty, "impacts_used", where_uncertainty).value_or(0);
      out.per_impact_scatter =
          NumberAt(uncertainty, "per_impact_scatter", where_uncertainty).value_or(0.0);
      out.between_recording_sd =
          NumberAt(uncertainty, "between_recording_sd", where_uncertainty).value_or(0.0);
      out.effective_dof = NumberAt(uncertainty, "effective_dof", where_uncertainty);
    }
    record.energy_loss_mean_measured = NumberAt(fit, "energy_loss_mean_measured", at);
    record.gamma_n_formula = NumberAt(fit, "gamma_n_formula", at);
    if (fit.contains("confidence_interval")) {
      for (const auto& [name, interval] : ObjectAt(fit, "confidence_interval", at).items()) {
        if (!interval.is_array() || interval.size() != 2 || !IsFiniteNumber(interval[0]) ||
            !IsFiniteNumber(interval[1])) {
          throw InputError(at + ": confidence_interval \"" + name +
                           "\" must be a pair of finite numbers [low, high], not " +
                           interval.dump());
        }
        record.confidence_interval[name] = {interval[0].get<double>(), interval[1].get<double>()};
      }
    }
  }
  if (object.contains("recordings")) {
    const auto& recordings = object["recordings"];
    if (!recordings.is_array()) {
      throw InputError(where + ": \"recordings\" must be an array, not " +
                       std::string(recordings.type_name()));
    }
    for (const auto& recording : recordings) {
      const std::string at = where + ": recordings[]";
      if (!recording.is_object()) {
        throw InputError(at + " entries must be objects {\"file\", \"content_hash\"}");
      }
      RejectUnknownKeys(recording, at, {"file", "content_hash", "drop_height_m", "first_n"});
      card.recordings.push_back({StringAt(recording, "file", at).value_or(""),
                                 StringAt(recording, "content_hash", at).value_or(""),
                                 NumberAt(recording, "drop_height_m", at),
                                 IntegerAt(recording, "first_n", at)});
    }
  }
  card.tool_version = StringAt(object, "tool_version", where).value_or("");
  card.created_utc = StringAt(object, "created_utc", where).value_or("");
  return card;
}

void WriteMaterialCard(const std::filesystem::path& path, const MaterialCard& card) {
  WriteFileAtomically(path, ToJson(card).dump(2) + "\n");
}

MaterialCard ReadMaterialCard(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) {
    throw InputError("cannot open material card '" + path.string() +
                     "'; check the path (calibrate writes one: `card`)");
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
