#ifndef BOUNCECAL_CALIBRATE_BALL_PRESET_H_
#define BOUNCECAL_CALIBRATE_BALL_PRESET_H_

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// A named ball whose size and mass (or density) come from a published specification, so a user
// can say `--ball tennis` instead of typing numbers, and the card records which ball it was.
// Solid balls give a density; hollow ones (ping-pong, tennis, squash, basketball) a mass.
struct BallPreset {
  std::string_view name;
  double diameter_m = 0;
  std::optional<double> density_kg_per_m3;
  std::optional<double> mass_kg;
  std::string_view source;  // where the numbers come from
  // How long the ball touches a rigid plate at drop speeds (a few m/s), where a published
  // measurement gives it; calibrate warns when the law's stiffness makes it far shorter or
  // longer (ContactDurationWarning). Unset: not known here, no warning.
  std::optional<double> contact_duration_s = std::nullopt;
  std::string_view contact_source = {};
  dem::Ball ToBall() const;
};

// Every preset, in a fixed order (help texts list them).
std::span<const BallPreset> BallPresets();
// "steel-10mm, glass-10mm, ..." for help texts and errors.
std::string BallPresetNames();
// Throws ConfigError naming the unknown name and listing the valid ones.
const BallPreset& FindBallPreset(std::string_view name);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_BALL_PRESET_H_
