#include "detector/clipped_span.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

constexpr std::int64_t kBridge = 10;
constexpr std::int64_t kReach = 1000;

SampleHistory<float> History(const std::vector<float>& samples) {
  SampleHistory<float> history(samples.size());
  for (float x : samples) history.Push(x);
  return history;
}

// A 3 kHz oscillation at 48 kHz, `gain` times full scale, clipped at full scale as a 16-bit
// converter does (the negative rail at -1, the positive at 32767 / 32768).
std::vector<float> ClippedTone(std::size_t samples, double gain) {
  std::vector<float> x(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    const double v = gain * std::sin(2 * std::numbers::pi * 3000.0 * static_cast<double>(i) / 48e3);
    x[i] = static_cast<float>(std::clamp(v, -1.0, 32767.0 / 32768.0));
  }
  return x;
}

// A tone clipped over its first 200 samples, then quiet: the stretch reaches the onset at 200
// (its last half cycle swings back inside full scale, which the bridge spans).
TEST(ClippedSpan, AClippedStretchUpToTheOnsetIsMeasuredFromItsStart) {
  auto x = ClippedTone(200, 3.0);
  x.resize(400, 0.01F);
  const auto history = History(x);
  const std::int64_t span = ClippedSamplesBefore(history, 200, kBridge, kReach);
  // The first clipped sample is where 3 sin reaches 1 (sin = 1/3, 1.1 samples in) and a clipped
  // run repeats its first value only from its second sample on.
  EXPECT_GE(span, 197);
  EXPECT_LE(span, 199);
}

TEST(ClippedSpan, AStretchEndingMoreThanTheBridgeBeforeTheOnsetIsNotTheOnsets) {
  auto x = ClippedTone(200, 3.0);
  x.resize(400, 0.01F);
  const auto history = History(x);
  EXPECT_EQ(ClippedSamplesBefore(history, 200 + kBridge + 8, kBridge, kReach), 0);
}

// The same tone just under full scale peaks there without repeating a value: not clipped.
TEST(ClippedSpan, APeakAtFullScaleThatDoesNotRepeatIsNoClipping) {
  auto x = ClippedTone(200, 0.999);
  x.resize(400, 0.01F);
  const auto history = History(x);
  EXPECT_EQ(ClippedSamplesBefore(history, 200, kBridge, kReach), 0);
}

// A float file above full scale (no clipping) repeats no value either.
TEST(ClippedSpan, AFloatSoundAboveFullScaleIsNoClipping) {
  std::vector<float> x(400, 0.01F);
  for (std::size_t i = 0; i < 200; ++i) {
    x[i] = static_cast<float>(3.0 * std::sin(2 * std::numbers::pi * 3000.0 * i / 48e3));
  }
  const auto history = History(x);
  EXPECT_EQ(ClippedSamplesBefore(history, 200, kBridge, kReach), 0);
}

TEST(ClippedSpan, TheLookBackStopsAtTheReachAndAtTheHistorysStart) {
  auto x = ClippedTone(200, 3.0);
  x.resize(400, 0.01F);
  const auto history = History(x);
  EXPECT_EQ(ClippedSamplesBefore(history, 200, kBridge, 50), 50);
  // A history holding only the last 64 samples of a clipped run looks back no further.
  std::vector<float> late(400, -1.0F);
  SampleHistory<float> held(64);
  for (float v : late) held.Push(v);
  EXPECT_EQ(ClippedSamplesBefore(held, 400, kBridge, kReach), 64);
}

// The timing reference's fraction of full scale: lobes under it never carried the reference.
constexpr float kMinLobe = 0.12F;

// A click's small first waves, then its spike clipped at the positive rail 20 samples on: the
// timing reference took the small waves' level against the clipped spike, which the true peak
// exceeds, so the onset may belong on the spike.
TEST(ClippedLobe, ASmallWaveBeforeAClippedSpikeLiesItsDistanceFromIt) {
  std::vector<float> x(100, 0.0F);
  for (std::size_t i = 0; i < 20; ++i) {
    x[40 + i] =
        static_cast<float>(0.2 * std::sin(std::numbers::pi * static_cast<double>(i) / 10.0));
  }
  for (std::size_t i = 60; i < 66; ++i) x[i] = 32767.0F / 32768.0F;
  const auto history = History(x);
  EXPECT_EQ(ClippedLobeAfter(history, 40, 48, kMinLobe), 20);
  // The horizon ends before the spike: nothing clipped ahead.
  EXPECT_EQ(ClippedLobeAfter(history, 40, 15, kMinLobe), 0);
}

// An onset on the clipped lobe's own rising edge, after noise of either sign: no lobe before it,
// so the clipping moves the reference along that edge only.
TEST(ClippedLobe, AnOnsetOnTheClippedLobesOwnEdgeIsNotDoubted) {
  std::vector<float> x(100, 0.0F);
  for (std::size_t i = 40; i < 50; ++i) x[i] = i % 2 ? 0.01F : -0.01F;
  for (std::size_t i = 0; i < 8; ++i) x[50 + i] = 0.15F * static_cast<float>(i + 1);
  for (std::size_t i = 58; i < 64; ++i) x[i] = 32767.0F / 32768.0F;
  const auto history = History(x);
  EXPECT_EQ(ClippedLobeAfter(history, 40, 48, kMinLobe), 0);
}

TEST(ClippedLobe, NoClippingAheadIsNoDoubt) {
  const auto history = History(ClippedTone(200, 0.5));
  EXPECT_EQ(ClippedLobeAfter(history, 10, 48, kMinLobe), 0);
}

}  // namespace
}  // namespace bouncecal::audio
