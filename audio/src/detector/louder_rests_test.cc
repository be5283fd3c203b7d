#include "detector/louder_rests.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

namespace bouncecal::audio {
namespace {

constexpr double kThresholdDb = 10.0;  // the detector's default rise threshold
constexpr double kFaintS = 2.2065;
constexpr double kRestS = 2.2149;  // 8.4 ms later: inside min_gap_ms, so one event
constexpr double kFaintSigmaS = 760e-6;

// What an impact timed on the faint sound states once half the gap to its rest is added.
double WidenedByHalfTheGap() { return std::hypot(kFaintSigmaS, 0.5 * (kRestS - kFaintS)); }

// One impact timed on a faint sound, with the rest of its sound `louder_db` louder after it.
DetectionResult FaintSoundWithALouderRest(double louder_db) {
  DetectionResult detection;
  Impact faint;
  faint.onset_s = kFaintS;
  faint.onset_uncertainty_s = kFaintSigmaS;
  faint.peak_dbfs = -46.7;
  detection.impacts.push_back(faint);
  MergedEvent rest;
  rest.time_s = kRestS;
  rest.winner_s = kFaintS;
  rest.peak_dbfs = -24.2;
  rest.rest_of_sound = true;
  rest.level_difference_db = -louder_db;
  rest.reason = "the rest of its sound";
  detection.merged.push_back(rest);
  return detection;
}

TEST(LouderRests, ARestTwoThresholdsLouderIsTheImpactInAnyFile) {
  auto detection = FaintSoundWithALouderRest(29.6);
  TakeLouderRestsAsImpacts(detection, std::nullopt, kThresholdDb);
  ASSERT_EQ(detection.impacts.size(), 1u);
  EXPECT_EQ(detection.impacts[0].onset_s, kRestS);
  EXPECT_EQ(detection.impacts[0].peak_dbfs, -24.2);
  // No codec could have joined the two: the faint sound is no candidate for the onset.
  EXPECT_EQ(detection.impacts[0].onset_uncertainty_s, kFaintSigmaS);
  const MergedEvent& set_aside = detection.merged[0];
  EXPECT_EQ(set_aside.time_s, kFaintS);
  EXPECT_EQ(set_aside.winner_s, kRestS);
  EXPECT_FALSE(set_aside.rest_of_sound);
  EXPECT_EQ(set_aside.level_difference_db, 29.6);
  EXPECT_NE(set_aside.reason.find("precursor 8.4 ms before"), std::string::npos)
      << set_aside.reason;
  EXPECT_EQ(set_aside.reason.find("codec"), std::string::npos) << set_aside.reason;
}

// A click 9-14 dB under its bounce that rang into it stays where the merger put it: which of the
// two the members are timed on is the bounce sequence's to weigh (merged_alternatives.h).
TEST(LouderRests, ARestLessThanTwoThresholdsLouderStaysTheRestWithoutACodec) {
  auto detection = FaintSoundWithALouderRest(19.0);
  TakeLouderRestsAsImpacts(detection, std::nullopt, kThresholdDb);
  EXPECT_EQ(detection.impacts[0].onset_s, kFaintS);
  EXPECT_EQ(detection.impacts[0].onset_uncertainty_s, kFaintSigmaS);
  EXPECT_TRUE(detection.merged[0].rest_of_sound);
  EXPECT_EQ(detection.merged[0].winner_s, kFaintS);
}

TEST(LouderRests, WithinACodecFrameOneThresholdMakesTheRestTheImpactAndHalfTheGapIsStated) {
  auto detection = FaintSoundWithALouderRest(12.0);
  TakeLouderRestsAsImpacts(detection, 1024.0 / 48000, kThresholdDb);
  EXPECT_EQ(detection.impacts[0].onset_s, kRestS);
  EXPECT_NEAR(detection.impacts[0].onset_uncertainty_s, WidenedByHalfTheGap(), 1e-12);
  EXPECT_NE(detection.merged[0].reason.find("codec"), std::string::npos);
}

TEST(LouderRests, WithinACodecFrameARestUnderOneThresholdOnlyWidensTheOnset) {
  auto detection = FaintSoundWithALouderRest(4.0);
  TakeLouderRestsAsImpacts(detection, 1024.0 / 48000, kThresholdDb);
  EXPECT_TRUE(detection.merged[0].rest_of_sound);
  EXPECT_EQ(detection.impacts[0].onset_s, kFaintS);
  EXPECT_NEAR(detection.impacts[0].onset_uncertainty_s, WidenedByHalfTheGap(), 1e-12);
}

// A codec's frame shorter than the gap: the rule of any file.
TEST(LouderRests, BeyondACodecFrameTheRuleOfAnyFileHolds) {
  auto quieter = FaintSoundWithALouderRest(12.0);
  TakeLouderRestsAsImpacts(quieter, 576.0 / 96000, kThresholdDb);
  EXPECT_EQ(quieter.impacts[0].onset_s, kFaintS);
  EXPECT_EQ(quieter.impacts[0].onset_uncertainty_s, kFaintSigmaS);
  auto louder = FaintSoundWithALouderRest(25.0);
  TakeLouderRestsAsImpacts(louder, 576.0 / 96000, kThresholdDb);
  EXPECT_EQ(louder.impacts[0].onset_s, kRestS);
  EXPECT_EQ(louder.impacts[0].onset_uncertainty_s, kFaintSigmaS);
}

// Two louder rests of one sound: the first moves the impact, and the second, whose level was
// measured against the faint sound, finds no impact there and stays as it was.
TEST(LouderRests, ASecondLouderRestOfAMovedImpactIsLeftAsItWas) {
  auto detection = FaintSoundWithALouderRest(29.6);
  MergedEvent later = detection.merged[0];
  later.time_s = kFaintS + 11e-3;
  later.level_difference_db = -25.0;
  detection.merged.push_back(later);
  TakeLouderRestsAsImpacts(detection, std::nullopt, kThresholdDb);
  EXPECT_EQ(detection.impacts[0].onset_s, kRestS);
  EXPECT_TRUE(detection.merged[1].rest_of_sound);
  EXPECT_EQ(detection.merged[1].time_s, kFaintS + 11e-3);
  EXPECT_EQ(detection.merged[1].winner_s, kFaintS);
}

// A merged precursor (not a rest) or an echo quieter than its impact is not touched.
TEST(LouderRests, OnlyLouderRestsAreConsidered) {
  auto precursor = FaintSoundWithALouderRest(29.6);
  precursor.merged[0].rest_of_sound = false;
  TakeLouderRestsAsImpacts(precursor, std::nullopt, kThresholdDb);
  EXPECT_EQ(precursor.impacts[0].onset_s, kFaintS);
  auto quieter_rest = FaintSoundWithALouderRest(-25.0);
  TakeLouderRestsAsImpacts(quieter_rest, 1024.0 / 48000, kThresholdDb);
  EXPECT_EQ(quieter_rest.impacts[0].onset_s, kFaintS);
  EXPECT_EQ(quieter_rest.impacts[0].onset_uncertainty_s, kFaintSigmaS);
}

}  // namespace
}  // namespace bouncecal::audio
