#include "bouncecal/export/drop_deck_check.h"

#include <fmt/core.h>

#include <cmath>
#include <fstream>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

double NumberAt(const nlohmann::json& object, std::string_view key, std::string_view context) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number() || !std::isfinite(it->get<double>())) {
    throw InputError(fmt::format("{}: key \"{}\" must be a finite number", context, key));
  }
  return it->get<double>();
}

std::string StringAt(const nlohmann::json& object, std::string_view key, std::string_view context) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string()) {
    throw InputError(fmt::format("{}: key \"{}\" must be a string", context, key));
  }
  return it->get<std::string>();
}

}  // namespace

nlohmann::json ToJson(const DropDeckRecord& record) {
  return {{"format", kDropDeckRecordFormat},
          {"engine", record.engine},
          {"tool_version", record.tool_version},
          {"material_card", record.material_source},
          {"trajectory_file", record.trajectory_file_name},
          {"run_command", record.run_command},
          {"ball_radius_m", record.ball_radius_m},
          {"wall_z_m", record.wall_z_m},
          {"gravity_mps2", record.gravity_mps2},
          {"time_step_s", record.time_step_s},
          {"expected",
           {{"restitution", record.expected_restitution},
            {"wall_contact_duration_s", record.expected_contact_duration_s},
            {"time_step_error_bound", record.time_step_error_bound}}}};
}

DropDeckRecord DropDeckRecordFromJson(const nlohmann::json& object, std::string_view context) {
  if (!object.is_object() || !object.contains("format") || !object["format"].is_string() ||
      object["format"].get<std::string>() != kDropDeckRecordFormat) {
    throw InputError(
        fmt::format("{}: key \"format\" must be \"{}\"; is this the deck.json of an "
                    "exported single-drop deck?",
                    context, kDropDeckRecordFormat));
  }
  DropDeckRecord record;
  record.engine = StringAt(object, "engine", context);
  record.tool_version = StringAt(object, "tool_version", context);
  record.material_source = StringAt(object, "material_card", context);
  record.trajectory_file_name = StringAt(object, "trajectory_file", context);
  record.run_command = StringAt(object, "run_command", context);
  record.ball_radius_m = NumberAt(object, "ball_radius_m", context);
  record.wall_z_m = NumberAt(object, "wall_z_m", context);
  record.gravity_mps2 = NumberAt(object, "gravity_mps2", context);
  record.time_step_s = NumberAt(object, "time_step_s", context);
  if (!object.contains("expected") || !object["expected"].is_object()) {
    throw InputError(fmt::format("{}: missing object \"expected\"", context));
  }
  const std::string expected_context = fmt::format("{}: expected", context);
  const auto& expected = object["expected"];
  record.expected_restitution = NumberAt(expected, "restitution", expected_context);
  record.expected_contact_duration_s =
      NumberAt(expected, "wall_contact_duration_s", expected_context);
  record.time_step_error_bound = NumberAt(expected, "time_step_error_bound", expected_context);
  return record;
}

DropDeckCheck CheckDropDeck(const DropDeckRecord& record,
                            const std::vector<TrajectorySample>& trajectory,
                            const DropDeckCheckOptions& options) {
  if (!(options.max_gravity_effect > 0) || !std::isfinite(options.max_gravity_effect)) {
    throw ConfigError(fmt::format("maximum gravity effect must be a positive fraction, got {}",
                                  options.max_gravity_effect));
  }
  const auto found = FindTrajectoryBounces(
      trajectory, {record.ball_radius_m, record.wall_z_m, record.gravity_mps2});
  DropDeckCheck check;
  check.unresolved_contacts = found.unresolved_contacts;
  for (const auto& bounce : found.bounces) {
    CheckedBounce checked;
    checked.bounce = bounce;
    checked.restitution_deviation = bounce.restitution / record.expected_restitution - 1;
    checked.duration_deviation =
        (bounce.contact_end_s - bounce.contact_start_s) / record.expected_contact_duration_s - 1;
    checked.gravity_effect =
        record.gravity_mps2 * record.expected_contact_duration_s / bounce.impact_speed_mps;
    checked.allowed_deviation = record.time_step_error_bound + checked.gravity_effect;
    checked.judged = checked.gravity_effect <= options.max_gravity_effect;
    // The engine detects touch and separation to within one step: that bounds the duration.
    const double allowed_duration =
        record.time_step_s / record.expected_contact_duration_s + checked.gravity_effect;
    checked.within = std::abs(checked.restitution_deviation) <= checked.allowed_deviation &&
                     std::abs(checked.duration_deviation) <= allowed_duration;
    if (checked.judged) {
      ++check.judged;
      if (checked.within) ++check.within;
    }
    check.bounces.push_back(checked);
  }
  check.passed = check.judged > 0 && check.within == check.judged;
  return check;
}

DropDeckCheck CheckDropDeckFolder(const std::filesystem::path& folder,
                                  const DropDeckCheckOptions& options) {
  const auto record_path = folder / kDropDeckRecordFileName;
  std::ifstream file(record_path);
  if (!file) {
    throw InputError(record_path.string() +
                     ": cannot open; give the folder bouncecal export wrote (it holds deck.json)");
  }
  nlohmann::json object;
  try {
    object = nlohmann::json::parse(file);
  } catch (const nlohmann::json::parse_error& error) {
    throw InputError(fmt::format("{}: not valid JSON (byte {})", record_path.string(), error.byte));
  }
  const auto record = DropDeckRecordFromJson(object, record_path.string());
  return CheckDropDeck(record, ReadTrajectory(folder / record.trajectory_file_name), options);
}

}  // namespace bouncecal::calibrate
