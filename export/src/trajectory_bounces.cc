#include "bouncecal/export/trajectory_bounces.h"

#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

bool IsBlankOrComment(std::string_view line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first == std::string_view::npos || line[first] == '#';
}

// Speed at the touching height of a drag-free ballistic flight seen at (z, vz).
double SpeedAtTouch(const TrajectorySample& sample, double touch_z_m, double gravity_mps2) {
  return std::sqrt(sample.vz_mps * sample.vz_mps +
                   2 * gravity_mps2 * std::max(0.0, sample.z_m - touch_z_m));
}

}  // namespace

std::vector<TrajectorySample> ParseTrajectory(std::string_view text, std::string_view source) {
  std::vector<TrajectorySample> samples;
  std::istringstream stream{std::string(text)};
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    if (IsBlankOrComment(line)) continue;
    std::istringstream fields(line);
    TrajectorySample sample;
    std::string extra;
    if (!(fields >> sample.time_s >> sample.z_m >> sample.vz_mps) || (fields >> extra) ||
        !std::isfinite(sample.time_s) || !std::isfinite(sample.z_m) ||
        !std::isfinite(sample.vz_mps)) {
      throw InputError(fmt::format(
          "{}:{}: expected three finite numbers 'time_s z_m vz_mps', got '{}'; is this the "
          "trajectory.txt of an exported single-drop deck?",
          source, line_number, line));
    }
    if (!samples.empty() && !(sample.time_s > samples.back().time_s)) {
      throw InputError(fmt::format(
          "{}:{}: time {} s does not increase after {} s; was the file appended to by two runs?",
          source, line_number, sample.time_s, samples.back().time_s));
    }
    samples.push_back(sample);
  }
  return samples;
}

std::vector<TrajectorySample> ReadTrajectory(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw InputError(path.string() +
                     ": cannot open the trajectory; run the exported deck first (it writes "
                     "trajectory.txt in the folder it runs in)");
  }
  std::ostringstream content;
  content << file.rdbuf();
  return ParseTrajectory(content.str(), path.string());
}

TrajectoryBounces FindTrajectoryBounces(const std::vector<TrajectorySample>& samples,
                                        const TrajectoryBounceOptions& options) {
  if (!(options.radius_m > 0) || !std::isfinite(options.radius_m)) {
    throw ConfigError(
        fmt::format("ball radius must be a positive number of metres, got {}", options.radius_m));
  }
  if (!(options.gravity_mps2 > 0) || !std::isfinite(options.gravity_mps2)) {
    throw ConfigError(
        fmt::format("gravity must be a positive number of m/s^2, got {}", options.gravity_mps2));
  }
  const double touch_z = options.wall_z_m + options.radius_m;
  const double g = options.gravity_mps2;
  auto in_contact = [&](const TrajectorySample& s) { return s.z_m < touch_z; };

  TrajectoryBounces result;
  size_t i = 0;
  const size_t n = samples.size();
  while (i + 1 < n) {
    if (in_contact(samples[i]) || !in_contact(samples[i + 1])) {
      ++i;
      continue;
    }
    const TrajectorySample& before = samples[i];
    size_t j = i + 1;
    while (j < n && in_contact(samples[j])) ++j;
    if (j == n) {
      result.ends_in_contact = true;
      break;
    }
    const TrajectorySample& after = samples[j];
    if (before.vz_mps < 0 && after.vz_mps > 0) {
      TrajectoryBounce bounce;
      bounce.impact_speed_mps = SpeedAtTouch(before, touch_z, g);
      bounce.rebound_speed_mps = SpeedAtTouch(after, touch_z, g);
      bounce.restitution = bounce.rebound_speed_mps / bounce.impact_speed_mps;
      // Free fall speeds up by g per second; so the flight from `before` to the touch lasted
      // (v_impact - |vz|) / g, and from the release to `after` (v_rebound - vz) / g.
      bounce.contact_start_s = before.time_s + (bounce.impact_speed_mps + before.vz_mps) / g;
      bounce.contact_end_s = after.time_s - (bounce.rebound_speed_mps - after.vz_mps) / g;
      result.bounces.push_back(bounce);
    } else {
      ++result.unresolved_contacts;
    }
    i = j;
  }
  return result;
}

}  // namespace bouncecal::calibrate
