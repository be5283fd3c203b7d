#include "bouncecal/calibrate/drop_height_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kG = 9.81;

// Onsets of an ideal drop from h0 with constant restitution e (instant contacts): the first
// impact after the fall sqrt(2 h0 / g), then flights 2 e^k sqrt(2 h0 / g).
std::vector<TimedImpact> IdealDrop(double h0, double e, int impacts, double sigma_s = 10e-6) {
  std::vector<TimedImpact> onsets;
  const double fall = std::sqrt(2 * h0 / kG);
  double t = fall, flight = 2 * fall;
  for (int k = 0; k < impacts; ++k) {
    onsets.push_back({t, sigma_s});
    flight *= e;
    t += flight;
  }
  return onsets;
}

RestitutionAnalysis Analyze(const std::vector<TimedImpact>& onsets, double h0) {
  RestitutionOptions options;
  options.drop_height_m = h0;
  return AnalyzeRestitution(onsets, options);
}

TEST(DropHeightCheck, TheTrueHeightIsConsistentAndImpliesItself) {
  const auto physics = Analyze(IdealDrop(0.2, 0.65, 8), 0.2);
  const auto check = CheckDropHeight(physics, 0.2, kG);
  ASSERT_TRUE(check.has_value());
  EXPECT_TRUE(check->consistent);
  EXPECT_NEAR(check->first_restitution, 0.65, 1e-9);
  EXPECT_EQ(check->later_impacts, DropHeightCheck::kLaterImpacts);
  // Exact flights: the later e_k equal e_1, so the implied height is h0 to rounding.
  EXPECT_NEAR(check->implied_drop_height_m, 0.2, 1e-9);
  EXPECT_NEAR(check->deviation_sigma, 0.0, 1e-6);
}

TEST(DropHeightCheck, AMissedFirstImpactIsInconsistentAndImpliesTheFirstApex) {
  // The recording starts at the second impact; the user gives the true release height.
  auto onsets = IdealDrop(1.5, 0.8, 10);
  onsets.erase(onsets.begin());
  const auto physics = Analyze(onsets, 1.5);
  const auto check = CheckDropHeight(physics, 1.5, kG);
  ASSERT_TRUE(check.has_value());
  EXPECT_FALSE(check->consistent);
  // e_1 = e^2 flight-wise: dt_1 is the second flight, dt_0 the fall from h0.
  EXPECT_NEAR(check->first_restitution, 0.8 * 0.8, 1e-9);
  EXPECT_LT(check->deviation_sigma, -DropHeightCheck::kMaxDeviationSigma);
  // The bounces imply a release from the apex of the missed first rebound, e^2 h0.
  EXPECT_NEAR(check->implied_drop_height_m, 0.64 * 1.5, 1e-9);
  const std::string message = DescribeInconsistentDropHeight("Audio_1.wav", *check);
  EXPECT_NE(message.find("Audio_1.wav: e_1 = 0.6400"), std::string::npos) << message;
  EXPECT_NE(message.find("release from 0.96 m"), std::string::npos) << message;
  EXPECT_NE(message.find("drop_height_m"), std::string::npos) << message;
}

TEST(DropHeightCheck, ATenPerCentWrongHeightOfAHighRestitutionBallIsCaught) {
  // e_1 scales as sqrt(h_true / h_given): a height 21 % too high lowers e_1 by 9 % (0.077 for
  // e = 0.85), within the 4 x 0.03 a consistent material may show, so it passes; a height twice
  // the true one lowers it by 29 % (0.25) and is caught.
  const auto onsets = IdealDrop(0.3, 0.85, 10);
  const auto slightly = CheckDropHeight(Analyze(onsets, 0.3 * 1.21), 0.3 * 1.21, kG);
  ASSERT_TRUE(slightly.has_value());
  EXPECT_TRUE(slightly->consistent) << "within what speed dependence and scatter can do";
  const auto doubled = CheckDropHeight(Analyze(onsets, 0.6), 0.6, kG);
  ASSERT_TRUE(doubled.has_value());
  EXPECT_FALSE(doubled->consistent);
  EXPECT_NEAR(doubled->implied_drop_height_m, 0.3, 1e-9);
}

TEST(DropHeightCheck, ScatterOfTheLaterImpactsWidensWhatIsConsistent) {
  // e_k alternating 0.55 / 0.75 (sd 0.11): an e_1 0.23 below the mean of the next
  // five (0.63) is within that scatter (z = -1.9).
  std::vector<TimedImpact> onsets{{0.0, 1e-6}};
  const double fall = std::sqrt(2 * 0.2 / kG);
  double flight = 2 * fall * 0.4;  // e_1 = 0.4
  const double es[] = {0.55, 0.75, 0.55, 0.75, 0.55, 0.75};
  onsets.push_back({onsets.back().onset_s + flight, 1e-6});
  for (double e : es) {
    flight *= e;
    onsets.push_back({onsets.back().onset_s + flight, 1e-6});
  }
  const auto check = CheckDropHeight(Analyze(onsets, 0.2), 0.2, kG);
  ASSERT_TRUE(check.has_value());
  EXPECT_NEAR(check->first_restitution, 0.4, 1e-9);
  EXPECT_TRUE(check->consistent) << check->deviation_sigma;
}

TEST(DropHeightCheck, NeedsAHeightAndALaterImpact) {
  RestitutionOptions no_height;
  EXPECT_FALSE(CheckDropHeight(AnalyzeRestitution(IdealDrop(0.2, 0.6, 6), no_height), 0.2, kG));
  // Two impacts: e_1 alone, nothing to compare it with.
  EXPECT_FALSE(CheckDropHeight(Analyze(IdealDrop(0.2, 0.6, 2), 0.2), 0.2, kG));
}

TEST(DropHeightCheck, AReboundAboveTheReleaseIsRefusedNamingTheField) {
  const auto onsets = IdealDrop(0.2, 0.8, 6);
  const auto physics = Analyze(onsets, 0.1);  // the first rebound rose to 0.128 m > 0.1 m
  try {
    RefuseReboundAboveRelease("drop.wav", physics, 0.1);
    ADD_FAILURE() << "not refused";
  } catch (const OptionError& error) {
    ASSERT_EQ(error.fields().size(), 1u);
    EXPECT_EQ(error.fields().front(), "drop_height_m");
    EXPECT_NE(std::string(error.what()).find("first rebound rose to 0.128 m"), std::string::npos)
        << error.what();
  }
  EXPECT_NO_THROW(RefuseReboundAboveRelease("drop.wav", Analyze(onsets, 0.2), 0.2));
}

TEST(Restitution, TheDropHeightUncertaintyWidensTheFirstImpactAsItsDerivativeSays) {
  const auto onsets = IdealDrop(0.2, 0.65, 6, 0.0);
  RestitutionOptions options;
  options.drop_height_m = 0.2;
  options.drop_height_uncertainty_m = 0.002;
  const auto physics = AnalyzeRestitution(onsets, options);
  // No timing error: sigma(e_1) = |d e_1 / d h0| sigma_h, by finite difference.
  RestitutionOptions higher = options;
  higher.drop_height_m = 0.2 + 1e-6;
  higher.drop_height_uncertainty_m = 0;
  const double slope =
      (AnalyzeRestitution(onsets, higher).restitution.front() - physics.restitution.front()) / 1e-6;
  EXPECT_NEAR(physics.restitution_uncertainty.front(), std::abs(slope) * 0.002, 1e-8);
  // Later impacts do not depend on h0.
  EXPECT_EQ(physics.restitution_uncertainty[1], 0.0);
  // eta-bar of the first 3 carries a third of eta_1's height error.
  EXPECT_NEAR(*physics.energy_loss_mean_first_n_uncertainty,
              physics.energy_loss_uncertainty.front() / 3, 1e-12);
}

}  // namespace
}  // namespace bouncecal::calibrate
