#include "bouncecal/calibrate/ball_choice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

// The OptionError a choice raises, so each test can read its message and its fields.
OptionError ErrorOf(const BallChoice& choice, BallCompletion completion) {
  try {
    ResolveBall(choice, completion);
  } catch (const OptionError& error) {
    return error;
  }
  ADD_FAILURE() << "no OptionError";
  return OptionError({}, "");
}

bool Names(const OptionError& error, const std::string& field) {
  const auto& fields = error.fields();
  return std::find(fields.begin(), fields.end(), field) != fields.end();
}

TEST(BallChoice, NothingGivenIsNoBall) {
  EXPECT_FALSE(ResolveBall({}, BallCompletion::kAsGiven).has_value());
  EXPECT_FALSE(ResolveBall({}, BallCompletion::kPaperBall).has_value());
}

TEST(BallChoice, APresetIsItsPublishedBall) {
  BallChoice choice;
  choice.preset = "tennis";
  const auto ball = ResolveBall(choice, BallCompletion::kAsGiven);
  ASSERT_TRUE(ball.has_value());
  EXPECT_DOUBLE_EQ(ball->diameter_m, FindBallPreset("tennis").diameter_m);
  EXPECT_DOUBLE_EQ(ball->MassKg(), *FindBallPreset("tennis").mass_kg);
}

TEST(BallChoice, AHollowBallIsItsSizeAndMassAndItsMeanDensityFollows) {
  BallChoice choice;
  choice.diameter_m = 0.04;
  choice.mass_kg = 0.0027;
  const auto ball = ResolveBall(choice, BallCompletion::kAsGiven);
  ASSERT_TRUE(ball.has_value());
  EXPECT_DOUBLE_EQ(ball->MassKg(), 0.0027);
  // 2.7 g in a 40 mm sphere: 0.0027 / (pi 0.04^3 / 6) = 80.6 kg/m^3, nowhere near steel.
  EXPECT_NEAR(ball->DensityKgPerM3(), 80.57, 0.01);
}

TEST(BallChoice, APresetWithNumbersIsRefusedNamingBoth) {
  BallChoice choice;
  choice.preset = "steel-10mm";
  choice.diameter_m = 0.02;
  const auto error = ErrorOf(choice, BallCompletion::kPaperBall);
  EXPECT_TRUE(Names(error, "ball"));
  EXPECT_TRUE(Names(error, "diameter_m"));
  EXPECT_NE(std::string(error.what()).find("names a preset"), std::string::npos);
}

TEST(BallChoice, DensityAndMassTogetherAreRefused) {
  BallChoice choice;
  choice.diameter_m = 0.01;
  choice.density_kg_per_m3 = 7800;
  choice.mass_kg = 0.004;
  const auto error = ErrorOf(choice, BallCompletion::kPaperBall);
  EXPECT_TRUE(Names(error, "density_kg_per_m3"));
  EXPECT_TRUE(Names(error, "mass_kg"));
}

TEST(BallChoice, AnExperimentsBallIsNeverCompletedFromThePapersBall) {
  BallChoice size_only;
  size_only.diameter_m = 0.067;
  EXPECT_NE(std::string(ErrorOf(size_only, BallCompletion::kAsGiven).what())
                .find("diameter_m needs density_kg_per_m3 or mass_kg"),
            std::string::npos);
  BallChoice mass_only;
  mass_only.mass_kg = 0.0577;
  EXPECT_NE(
      std::string(ErrorOf(mass_only, BallCompletion::kAsGiven).what()).find("needs diameter_m"),
      std::string::npos);
}

TEST(BallChoice, ASimulationsBallTakesWhatIsLeftOutFromThePapersBall) {
  BallChoice size_only;
  size_only.diameter_m = 0.02;
  const auto ball = ResolveBall(size_only, BallCompletion::kPaperBall);
  ASSERT_TRUE(ball.has_value());
  EXPECT_DOUBLE_EQ(ball->diameter_m, 0.02);
  EXPECT_DOUBLE_EQ(ball->density_kg_per_m3, dem::Ball{}.density_kg_per_m3);
}

TEST(BallChoice, ValuesOutsideTheDropsRangesAreRefusedNamingTheField) {
  // The ranges are dem::Ball's: every ball ResolveBall accepts must pass Ball::Validate, or a
  // simulation would refuse it later naming a member the user never typed.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    BallChoice choice;
    const char* field;
  };
  const Case cases[] = {
      {{std::nullopt, 20.0, 7800.0, std::nullopt}, "diameter_m"},
      {{std::nullopt, 0.0, 7800.0, std::nullopt}, "diameter_m"},
      {{std::nullopt, nan, 7800.0, std::nullopt}, "diameter_m"},
      {{std::nullopt, 0.01, 0.5, std::nullopt}, "density_kg_per_m3"},
      {{std::nullopt, 0.01, 2e5, std::nullopt}, "density_kg_per_m3"},
      {{std::nullopt, 0.01, std::nullopt, 0.0}, "mass_kg"},
      {{std::nullopt, 0.01, std::nullopt, -1.0}, "mass_kg"},
      {{std::nullopt, 0.01, std::nullopt, 2e6}, "mass_kg"},
  };
  for (const auto& c : cases) {
    const auto error = ErrorOf(c.choice, BallCompletion::kAsGiven);
    EXPECT_EQ(error.fields(), std::vector<std::string>{c.field}) << error.what();
    EXPECT_EQ(std::string(error.what()).find("nan"), std::string::npos) << error.what();
  }
  for (const double d : {dem::Ball::kMinDiameterM, dem::Ball::kMaxDiameterM}) {
    BallChoice edge;
    edge.diameter_m = d;
    edge.density_kg_per_m3 = dem::Ball::kMaxDensityKgPerM3;
    const auto ball = ResolveBall(edge, BallCompletion::kAsGiven);
    ASSERT_TRUE(ball.has_value());
    EXPECT_NO_THROW(ball->Validate());
  }
}

}  // namespace
}  // namespace bouncecal::calibrate
