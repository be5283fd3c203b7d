#include "bouncecal/calibrate/ball_preset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

TEST(BallPreset, SteelTenMillimetreIsThePapersBall) {
  // docs/physics.md: m = rho pi d^3 / 6 = 4.08 g for 1 cm of steel at 7800 kg/m^3.
  const auto ball = FindBallPreset("steel-10mm").ToBall();
  EXPECT_DOUBLE_EQ(ball.diameter_m, 0.01);
  EXPECT_NEAR(ball.MassKg(), 4.084e-3, 1e-6);
}

TEST(BallPreset, HollowBallsCarryTheirRegulationMass) {
  EXPECT_DOUBLE_EQ(FindBallPreset("pingpong-40mm").ToBall().MassKg(), 0.0027);
  EXPECT_DOUBLE_EQ(FindBallPreset("tennis").ToBall().diameter_m, 0.067);
  // A basketball's size-7 circumference range 749-780 mm has its middle at pi d = 764.5 mm.
  EXPECT_NEAR(std::numbers::pi * FindBallPreset("basketball-size7").diameter_m, 0.7645, 1e-3);
}

TEST(BallPreset, EveryPresetIsAValidBallWithAUniqueNameAndASource) {
  std::set<std::string_view> names;
  for (const auto& preset : BallPresets()) {
    EXPECT_TRUE(names.insert(preset.name).second) << preset.name;
    EXPECT_NO_THROW(preset.ToBall().Validate()) << preset.name;
    EXPECT_NE(preset.density_kg_per_m3.has_value(), preset.mass_kg.has_value()) << preset.name;
    EXPECT_FALSE(preset.source.empty()) << preset.name;
    EXPECT_EQ(&FindBallPreset(preset.name), &preset);
  }
}

TEST(BallPreset, UnknownNameIsAConfigErrorListingTheNames) {
  try {
    FindBallPreset("bowling");
    FAIL() << "no error";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("steel-10mm"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("bowling"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace bouncecal::calibrate
