#ifndef BOUNCECAL_EXPORT_DROP_DECK_CHECK_H_
#define BOUNCECAL_EXPORT_DROP_DECK_CHECK_H_

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/export/trajectory_bounces.h"

namespace bouncecal::calibrate {

inline constexpr std::string_view kDropDeckRecordFormat = "bouncecal-drop-deck/1";
inline constexpr std::string_view kDropDeckRecordFileName = "deck.json";

// What an exported single-drop deck promises, written beside it as deck.json so the run can be
// checked later without the card: the geometry the trajectory needs and the expected figures.
struct DropDeckRecord {
  std::string engine;
  std::string tool_version;
  std::string material_source;
  std::string trajectory_file_name = "trajectory.txt";
  std::string run_command;
  double ball_radius_m = 0;
  double wall_z_m = 0;
  double gravity_mps2 = 0;
  double time_step_s = 0;
  double expected_restitution = 0;
  double expected_contact_duration_s = 0;  // wall contact
  double time_step_error_bound = 0;        // relative, on the restitution
};

nlohmann::json ToJson(const DropDeckRecord& record);
// Throws InputError naming `context` and the key when the record is malformed.
DropDeckRecord DropDeckRecordFromJson(const nlohmann::json& object, std::string_view context);

struct DropDeckCheckOptions {
  // Bounces slower than this are reported but not judged: there gravity during the contact
  // (about g t_c / v, which no closed form includes) outweighs what the check is about.
  double max_gravity_effect = 0.01;
};

struct CheckedBounce {
  TrajectoryBounce bounce;
  double restitution_deviation = 0;  // e / e_expected - 1
  double duration_deviation = 0;     // t_c / t_c_expected - 1
  double gravity_effect = 0;         // g t_c / v_impact
  double allowed_deviation = 0;      // time-step bound + gravity effect
  bool judged = false;               // gravity_effect <= max_gravity_effect
  bool within = false;               // |both deviations| <= allowed (judged bounces only)
};

struct DropDeckCheck {
  std::vector<CheckedBounce> bounces;
  int judged = 0;
  int within = 0;
  int unresolved_contacts = 0;
  bool passed = false;  // at least one judged bounce and every judged bounce within
};

// Compares an engine's trajectory with what the deck promised. Throws ConfigError for options
// outside their range.
DropDeckCheck CheckDropDeck(const DropDeckRecord& record,
                            const std::vector<TrajectorySample>& trajectory,
                            const DropDeckCheckOptions& options = {});

// Reads deck.json and the trajectory it names from a deck folder (InputError when missing).
DropDeckCheck CheckDropDeckFolder(const std::filesystem::path& folder,
                                  const DropDeckCheckOptions& options = {});

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_DROP_DECK_CHECK_H_
