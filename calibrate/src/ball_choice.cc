#include "bouncecal/calibrate/ball_choice.h"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

const std::vector<std::string> kBallFields = {"ball", "diameter_m", "density_kg_per_m3", "mass_kg"};

// dem::Ball::Validate holds the same ranges; this one names the option the user typed, where the
// drop's check can only name the ball's member.
void CheckBallValue(const char* field, double value, double min_value, bool min_exclusive,
                    double max_value, const char* unit, const char* what) {
  if (!std::isfinite(value)) {
    throw OptionError({field}, fmt::format("{} is not a finite number; give {}", field, what));
  }
  const bool above_min = min_exclusive ? value > min_value : value >= min_value;
  if (above_min && value <= max_value) return;
  throw OptionError(
      {field}, fmt::format("{} = {:g} {} is outside {}{:g}, {:g}] {}; give {}", field, value, unit,
                           min_exclusive ? "(" : "[", min_value, max_value, unit, what));
}

}  // namespace

std::optional<dem::Ball> ResolveBall(const BallChoice& choice, BallCompletion completion) {
  const bool explicit_ball = choice.diameter_m || choice.density_kg_per_m3 || choice.mass_kg;
  if (choice.preset) {
    if (explicit_ball) {
      throw OptionError(kBallFields,
                        "`ball` names a preset (" + *choice.preset +
                            "); give either it or diameter_m with density_kg_per_m3 or mass_kg, "
                            "not both");
    }
    return FindBallPreset(*choice.preset).ToBall();
  }
  if (!explicit_ball) return std::nullopt;
  if (choice.density_kg_per_m3 && choice.mass_kg) {
    throw OptionError({"density_kg_per_m3", "mass_kg"},
                      "density_kg_per_m3 and mass_kg both give the ball's mass; give one of them");
  }
  if (completion == BallCompletion::kAsGiven) {
    if (!choice.diameter_m) {
      throw OptionError(kBallFields,
                        "density_kg_per_m3 or mass_kg needs diameter_m (the ball's size), or name "
                        "a preset with `ball`");
    }
    if (!choice.density_kg_per_m3 && !choice.mass_kg) {
      throw OptionError(kBallFields,
                        "diameter_m needs density_kg_per_m3 or mass_kg (the ball's mass), or name "
                        "a preset with `ball`");
    }
  }
  dem::Ball ball;  // under kPaperBall, what is left out stays the 1 cm steel ball's
  if (choice.diameter_m) {
    CheckBallValue("diameter_m", *choice.diameter_m, dem::Ball::kMinDiameterM, false,
                   dem::Ball::kMaxDiameterM, "m", "the ball's diameter in metres");
    ball.diameter_m = *choice.diameter_m;
  }
  if (choice.density_kg_per_m3) {
    CheckBallValue("density_kg_per_m3", *choice.density_kg_per_m3, dem::Ball::kMinDensityKgPerM3,
                   false, dem::Ball::kMaxDensityKgPerM3, "kg/m^3",
                   "a solid ball's density (for a hollow ball, its mass with `mass_kg`)");
    ball.density_kg_per_m3 = *choice.density_kg_per_m3;
  }
  if (choice.mass_kg) {
    CheckBallValue("mass_kg", *choice.mass_kg, 0, true, dem::Ball::kMaxMassKg, "kg",
                   "the ball's mass in kilograms");
    ball.mass_kg = choice.mass_kg;
  }
  return ball;
}

}  // namespace bouncecal::calibrate
