#include "bouncecal/calibrate/ball_preset.h"

#include <array>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

// Regulation balls take the middle of the range their rules allow; the spread of that range is
// a few per cent of the mass, which moves a speed-dependent law's parameter far less than the
// impact-to-impact scatter of a real recording.
const std::array<BallPreset, 7> kPresets = {{
    {"steel-10mm", 0.010, 7800.0, std::nullopt,
     "bearing-steel sphere of paper 000 (d = 1 cm, 7800 kg/m^3, m = 4.08 g)"},
    {"glass-10mm", 0.010, 2500.0, std::nullopt,
     "soda-lime glass bead (2500 kg/m^3, the usual value for soda-lime glass), m = 1.31 g"},
    {"pingpong-40mm", 0.040, std::nullopt, 0.0027,
     "table-tennis ball, ITTF rule 2.3: 40 mm, 2.7 g (hollow)"},
    {"tennis", 0.067, std::nullopt, 0.0577,
     "ITF approved ball: 6.54-6.86 cm, 56.0-59.4 g; middle of both ranges (hollow)", 5e-3,
     "H. Brody: about 5 ms on a court; R. Cross, Sports Eng. 2 (1999) 23-33, force-plate drops"},
    {"squash", 0.040, std::nullopt, 0.024,
     "WSF double-yellow squash ball: 40.0 +- 0.5 mm, 24 +- 1 g (hollow rubber)"},
    {"golf", 0.04267, std::nullopt, 0.04593,
     "USGA/R&A: diameter at least 42.67 mm, mass at most 45.93 g (the limits)"},
    {"basketball-size7", 0.2434, std::nullopt, 0.6085,
     "FIBA size 7: circumference 749-780 mm, 567-650 g; middle of both ranges (hollow)"},
}};

}  // namespace

dem::Ball BallPreset::ToBall() const {
  dem::Ball ball;
  ball.diameter_m = diameter_m;
  if (density_kg_per_m3) ball.density_kg_per_m3 = *density_kg_per_m3;
  ball.mass_kg = mass_kg;
  return ball;
}

std::span<const BallPreset> BallPresets() { return kPresets; }

std::string BallPresetNames() {
  std::string names;
  for (const auto& preset : kPresets) {
    if (!names.empty()) names += ", ";
    names += preset.name;
  }
  return names;
}

const BallPreset& FindBallPreset(std::string_view name) {
  for (const auto& preset : kPresets) {
    if (preset.name == name) return preset;
  }
  throw OptionError({"ball", "diameter_m", "density_kg_per_m3", "mass_kg"},
                    "unknown ball '" + std::string(name) + "'; use one of " + BallPresetNames() +
                        ", or give diameter_m with density_kg_per_m3 or mass_kg");
}

}  // namespace bouncecal::calibrate
