#ifndef BOUNCECAL_EXPORT_TRAJECTORY_BOUNCES_H_
#define BOUNCECAL_EXPORT_TRAJECTORY_BOUNCES_H_

#include <filesystem>
#include <string_view>
#include <vector>

namespace bouncecal::calibrate {

// One line of the trajectory.txt an exported single-drop deck writes: time, height of the
// ball's centre above the origin and its vertical velocity, SI.
struct TrajectorySample {
  double time_s = 0;
  double z_m = 0;
  double vz_mps = 0;
};

// Reads whitespace-separated "time z vz" lines; blank lines and lines starting with '#' are
// skipped. Throws InputError naming the file and line for anything else, or when the times do
// not increase.
std::vector<TrajectorySample> ReadTrajectory(const std::filesystem::path& path);
// Same, from text already in memory; `source` names it in error messages.
std::vector<TrajectorySample> ParseTrajectory(std::string_view text, std::string_view source);

struct TrajectoryBounceOptions {
  // The ball touches the wall while its centre is below wall_z_m + radius_m.
  double radius_m = 0.005;
  double wall_z_m = 0;
  double gravity_mps2 = 9.81;
};

// One contact bracketed by free-flight samples. Speeds are extrapolated ballistically from those
// samples to the touching height, v^2 = vz^2 + 2 g (z - z_touch), which is exact for the
// drag-free flight of the exported decks; so the output interval only has to leave at least one
// sample of free flight between contacts, not resolve the contact itself.
struct TrajectoryBounce {
  double contact_start_s = 0;  // extrapolated instant the ball reaches the touching height
  double contact_end_s = 0;    // extrapolated instant it leaves it
  double impact_speed_mps = 0;
  double rebound_speed_mps = 0;
  double restitution = 0;  // rebound / impact speed
};

struct TrajectoryBounces {
  std::vector<TrajectoryBounce> bounces;
  // Contacts whose bracketing samples do not show vz changing from downward to upward (the
  // output interval is too coarse to separate two contacts), left out of `bounces`.
  int unresolved_contacts = 0;
  // True when the trajectory ends inside a contact (typically: the ball has come to rest).
  bool ends_in_contact = false;
};

// Finds every contact with the wall (vz changes sign from down to up across it) and its
// restitution. Throws ConfigError for a non-positive radius or gravity.
TrajectoryBounces FindTrajectoryBounces(const std::vector<TrajectorySample>& samples,
                                        const TrajectoryBounceOptions& options = {});

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_TRAJECTORY_BOUNCES_H_
