#include "detector/later_attack.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

constexpr int kRate = 48000;

// A plate's response to a hit `at_s` after the onset: a 3 kHz mode decaying over 10 ms, peak
// `amplitude`.
void AddHit(std::vector<float>& x, double at_s, double amplitude) {
  const auto start = static_cast<std::size_t>(at_s * kRate);
  for (std::size_t i = start; i < x.size(); ++i) {
    const double t = static_cast<double>(i - start) / kRate;
    x[i] += static_cast<float>(amplitude * std::exp(-t / 10e-3) *
                               std::sin(2 * std::numbers::pi * 3000 * t + 0.5));
  }
}

TEST(LaterAttack, AHitAtTheOnsetHasNoLaterAttack) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.5);
  EXPECT_EQ(LaterAttackS(x, kRate), 0.0);
}

// Pre-echo: the codec's noise 20 dB under the attack for 6 ms, then the attack. The onset the
// detector took is the noise's start, and the attack is 6 ms later.
TEST(LaterAttack, NoiseWellBelowALaterHitPointsToTheHit) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<float>(0.05 * std::sin(2 * std::numbers::pi * 9000 * i / kRate));
  }
  AddHit(x, 6e-3, 0.5);
  EXPECT_NEAR(LaterAttackS(x, kRate), 6e-3, 0.2e-3);
}

// The early part less than the rise threshold (10 dB) under the peak is the attack: nothing to
// say.
TEST(LaterAttack, AnEarlyPartWithinTheRiseThresholdOfThePeakIsTheAttack) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.2);
  AddHit(x, 6e-3, 0.5);
  EXPECT_EQ(LaterAttackS(x, kRate), 0.0);
}

TEST(LaterAttack, SilenceAndNothingGiveNoAttack) {
  const std::vector<float> silence(800, 0.0f);
  EXPECT_EQ(LaterAttackS(silence, kRate), 0.0);
  EXPECT_EQ(LaterAttackS({}, kRate), 0.0);
}

// A click 12 dB under its bounce, 5 ms before it, ringing into it: the bounce's start is picked
// as an onset is, within four samples (83 us). The click's ringing, the picker's noise here, is a
// tone 16 dB under the hit, not the white noise its edge fit assumes, and tilts the fit by up to
// three samples; a move to the later sound is worth milliseconds (merged_alternatives.h).
TEST(LaterSound, AClickThatRingsIntoItsBounceGivesTheBouncesStart) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.125);
  AddHit(x, 5e-3, 0.5);
  const auto later = LaterSoundOnsetS(x, kRate);
  ASSERT_TRUE(later);
  EXPECT_NEAR(*later, 5e-3, 4.0 / kRate);
}

TEST(LaterSound, AHitAtTheOnsetHasNone) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.5);
  EXPECT_FALSE(LaterSoundOnsetS(x, kRate));
  EXPECT_FALSE(LaterSoundOnsetS({}, kRate));
}

// The click 12 dB under its bounce (amplitudes 0.125 and 0.5), 5 ms (15 periods) before it, so
// its ring, down to exp(-0.5) of the click, adds in phase to the bounce's peak: 13.3 dB over the
// first millisecond, within what sampling the two peaks moves (0.2 dB).
TEST(LaterSound, ItsPeakOverTheFirstMillisecondIsTheLevelDifference) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.125);
  AddHit(x, 5e-3, 0.5);
  EXPECT_NEAR(PeakOverFirstMillisecondDb(x, kRate),
              20 * std::log10((0.5 + 0.125 * std::exp(-0.5)) / 0.125), 0.2);
  std::vector<float> one(17 * kRate / 1000, 0.0f);
  AddHit(one, 0.0, 0.5);
  EXPECT_EQ(PeakOverFirstMillisecondDb(one, kRate), 0.0);
  EXPECT_EQ(PeakOverFirstMillisecondDb({}, kRate), 0.0);
}

// A limiter holds a click and its bounce at one ceiling: two equal hits 5 ms apart. The bounce
// is no louder than the click's first millisecond, so no later sound is offered, but its attack
// out of the click's ringing (down to exp(-0.5) of the click, in phase) is a fresh rise: the
// energy of its first 0.5 ms over the 2 ms before, (0.5 e^-0.5 + 0.5 e^-0.025)^2 / (0.5 e^-0.4)^2
// ~ 7.4 dB averaged over the oscillation, found where the bounce begins (to one sample) and
// within 0.3 dB (the windows' part periods: 1.5 and 6 periods of 3 kHz).
TEST(LaterRise, ABounceLevelledWithItsClickRisesFreshOutOfItsRinging) {
  std::vector<float> x(17 * kRate / 1000, 0.0f);
  AddHit(x, 0.0, 0.5);
  AddHit(x, 5e-3, 0.5);
  EXPECT_FALSE(LaterSoundOnsetS(x, kRate));
  const auto rise = SharpestLaterRise(x, kRate);
  ASSERT_TRUE(rise);
  EXPECT_NEAR(rise->after_onset_s, 5e-3, 1.0 / kRate);
  EXPECT_NEAR(rise->rise_db, 7.4, 0.3);
}

// One hit's ringing only decays, and two modes beating (3 and 3.3 kHz, equal amplitude: the
// peak swings to zero every 3.3 ms) raise the energy of 0.5 ms over the 2 ms before by 5.0 dB
// at most, under the 6 dB that marks a fresh attack (merged_alternatives.cc): the 2 ms average
// spans most of a beat's trough.
TEST(LaterRise, RingingAloneHasNoFreshRise) {
  std::vector<float> one(17 * kRate / 1000, 0.0f);
  AddHit(one, 0.0, 0.5);
  const auto decay = SharpestLaterRise(one, kRate);
  ASSERT_TRUE(decay);
  EXPECT_LT(decay->rise_db, 0.0);
  std::vector<float> beating = one;
  const double omega = 2 * std::numbers::pi * 3300;
  for (std::size_t i = 0; i < beating.size(); ++i) {
    const double t = static_cast<double>(i) / kRate;
    beating[i] += static_cast<float>(0.5 * std::exp(-t / 10e-3) * std::sin(omega * t + 0.5));
  }
  const auto beat = SharpestLaterRise(beating, kRate);
  ASSERT_TRUE(beat);
  EXPECT_LT(beat->rise_db, 5.5);
}

TEST(LaterRise, TooShortOrSilentGivesNone) {
  EXPECT_FALSE(SharpestLaterRise({}, kRate));
  const std::vector<float> short_one(2 * kRate / 1000, 0.5f);
  EXPECT_FALSE(SharpestLaterRise(short_one, kRate));
  const std::vector<float> silence(17 * kRate / 1000, 0.0f);
  EXPECT_FALSE(SharpestLaterRise(silence, kRate));
}

}  // namespace
}  // namespace bouncecal::audio
