#include "bouncecal/calibrate/jittered_drop.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

RestitutionAnalysis Analyze(const MeasuredSequence& sequence, double drop_height_m) {
  RestitutionOptions options;
  options.drop_height_m = drop_height_m;
  return AnalyzeRestitution(sequence.impacts, options);
}

TEST(JitteredDrop, WithoutJitterOrNoiseEveryImpactHasTheMaterialsRestitution) {
  JitteredDropOptions options;
  options.relative_jitter = 0;
  options.timing_sigma_s = 0;
  options.impacts = 10;
  const auto sequence = JitteredDrop(options);
  ASSERT_EQ(sequence.impacts.size(), 10u);
  // The first impact comes after the fall sqrt(2 h / g) from the release.
  EXPECT_NEAR(sequence.impacts.front().onset_s, 0.5 + std::sqrt(2 * 0.2 / 9.81), 1e-12);
  const auto analysis = Analyze(sequence, options.drop_height_m);
  ASSERT_EQ(analysis.restitution.size(), 9u);
  // Ratios of sums of doubles: exact to rounding (1e-12 of an interval).
  for (double e : analysis.restitution) EXPECT_NEAR(e, 0.65, 1e-10);
  EXPECT_NEAR(MaterialEnergyLoss(options), 1 - 0.65 * 0.65, 1e-15);
}

TEST(JitteredDrop, RestitutionScattersByTheRequestedRelativeJitter) {
  JitteredDropOptions options;
  options.timing_sigma_s = 0;
  options.relative_jitter = 0.03;
  options.restitution = 0.8;  // keeps 100 flights above rounding
  options.impacts = 101;
  options.drop_height_m = 1e6;  // long flights, so 100 factors of 0.8 stay resolvable
  double sum = 0, squares = 0;
  int count = 0;
  for (std::uint64_t recording = 0; recording < 20; ++recording) {
    options.recording = recording;
    for (double e : Analyze(JitteredDrop(options), options.drop_height_m).restitution) {
      const double relative = e / 0.8 - 1;
      sum += relative;
      squares += relative * relative;
      ++count;
    }
  }
  // 2000 draws: the mean's standard error is 0.03 / sqrt(2000) = 6.7e-4, the sd's 2.2 % of 0.03;
  // both checked to 4 standard errors.
  EXPECT_NEAR(sum / count, 0.0, 2.7e-3);
  EXPECT_NEAR(std::sqrt(squares / count), 0.03, 0.0027);
}

TEST(JitteredDrop, MeanEnergyLossOfManyImpactsIsTheMaterials) {
  JitteredDropOptions options;
  options.relative_jitter = 0.05;
  options.recording_relative_offset = 0.02;
  options.timing_sigma_s = 0;
  options.impacts = 5;
  double sum = 0;
  int count = 0;
  for (std::uint64_t recording = 0; recording < 20000; ++recording) {
    options.recording = recording;
    for (double eta : Analyze(JitteredDrop(options), options.drop_height_m).energy_loss) {
      sum += eta;
      ++count;
    }
  }
  // A recording's mean eta has variance (2 e^2)^2 (b^2 + j^2 / 5) = 6.4e-4, so 20000 of them
  // give a standard error of 1.8e-4; checked to 4 of them, which also tells the formula from
  // 1 - e^2: the scatter's own contribution e^2 (j^2 + b^2 + j^2 b^2) is 1.2e-3.
  EXPECT_NEAR(sum / count, MaterialEnergyLoss(options), 7e-4);
  EXPECT_NEAR(1 - 0.65 * 0.65 - MaterialEnergyLoss(options), 1.2e-3, 1e-4);
}

TEST(JitteredDrop, SameSeedSameOnsetsOtherRecordingOtherOnsets) {
  JitteredDropOptions options;
  const auto a = JitteredDrop(options);
  const auto b = JitteredDrop(options);
  options.recording = 1;
  const auto c = JitteredDrop(options);
  for (size_t k = 0; k < a.impacts.size(); ++k)
    EXPECT_EQ(a.impacts[k].onset_s, b.impacts[k].onset_s);
  EXPECT_NE(a.impacts[3].onset_s, c.impacts[3].onset_s);
  EXPECT_EQ(a.impacts[0].uncertainty_s, options.timing_sigma_s);
}

TEST(JitteredDrop, OptionsOutsideTheirRangeAreConfigErrors) {
  JitteredDropOptions options;
  options.restitution = 1.2;
  EXPECT_THROW(JitteredDrop(options), ConfigError);
  options = {};
  options.impacts = 1;
  EXPECT_THROW(JitteredDrop(options), ConfigError);
  options = {};
  options.relative_jitter = -0.1;
  EXPECT_THROW(JitteredDrop(options), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
