#include "detector/novelty_sources.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "detector/stage_test_support.h"
#include "detector/test_signals.h"

namespace bouncecal::audio {
namespace {

constexpr int kRate = 48000;

void AddTone(std::vector<float>& x, double hz, double amplitude, double decay_s = 1e9) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / kRate;
    x[i] += static_cast<float>(amplitude * std::exp(-t / decay_s) *
                               std::sin(2 * std::numbers::pi * hz * t));
  }
}

// A click of a few cycles at 9 kHz, 40 dB under a 700 Hz hum that fills band 0: in band 0 the
// hum hides it, the sub-band above 6 kHz sees it rise out of its noise. The band rise is the
// best band's, and it names that band, where the onset is then picked.
TEST(BandRiseNovelty, TheBandThatRoseMostWinsAndIsNamed) {
  std::vector<float> x(kRate / 2, 0.0f);
  testing::AddNoise(x, 1e-5, 4);
  AddTone(x, 700.0, 0.3);
  const double click_s = 0.3;
  for (int i = 0; i < 40; ++i) {
    const double t = i / static_cast<double>(kRate);
    x[static_cast<std::size_t>(click_s * kRate) + static_cast<std::size_t>(i)] +=
        static_cast<float>(3e-3 * std::exp(-t / 3e-4) *
                           std::sin(2 * std::numbers::pi * 9000.0 * t));
  }
  testing::StageRig rig(kRate);
  BandRiseNovelty novelty(rig.bands);
  NoveltyRise best;
  double band0_best = -1e9;
  const auto click_frame = static_cast<std::int64_t>(click_s / rig.frames.frame_s);
  rig.Run(x, [&](std::int64_t n, std::ptrdiff_t k) {
    const std::int64_t m = n - rig.frames.attack;
    if (m < rig.frames.lookback || m < click_frame - rig.frames.attack || m > click_frame) return;
    const NoveltyRise rise = novelty.Rise(n, k, true);
    if (rise.rise_db > best.rise_db) best = rise;
    band0_best = std::max(band0_best, rig.bands.Rise(0, k));
  });
  EXPECT_EQ(best.band, 2u);
  EXPECT_GT(best.rise_db, 20.0);
  EXPECT_LT(band0_best, 5.0);
}

// Inside a loud decaying tail (tones at 1.1-4.7 kHz, the levels a plate rings with) a weak
// broadband impact rises in no band by the threshold but is new in many bins: the residual's
// novelty rises there, on the band scale. In plain noise, with no tail, the residual says
// nothing.
TEST(RingingResidualNovelty, RisesForANewImpactInsideATailAndIsSilentWithoutOne) {
  std::vector<float> tail(kRate, 0.0f);
  testing::AddNoise(tail, 1e-4, 6);
  for (double hz : {1100.0, 2300.0, 3100.0, 4700.0}) AddTone(tail, hz, 0.1, 0.5);
  auto with_impact = tail;
  testing::AddImpact(with_impact, kRate, 0.6, 0.02);
  std::vector<float> noise(kRate, 0.0f);
  testing::AddNoise(noise, 1e-3, 6);
  const auto max_rise = [](const std::vector<float>& x, double from_s, double to_s) {
    testing::StageRig rig(kRate);
    double best = -std::numeric_limits<double>::infinity();
    rig.Run(x, [&](std::int64_t n, std::ptrdiff_t k) {
      const double t = static_cast<double>(n - rig.frames.attack) * rig.frames.frame_s;
      if (n - rig.frames.attack < rig.frames.lookback || t < from_s || t > to_s) return;
      best = std::max(best, rig.residual.Rise(n, k, true).rise_db);
    });
    return best;
  };
  EXPECT_GE(max_rise(with_impact, 0.595, 0.61), 0.5 * DetectorOptions{}.rise_threshold_db);
  EXPECT_LT(max_rise(tail, 0.595, 0.61), 0.5 * DetectorOptions{}.rise_threshold_db);
  EXPECT_EQ(max_rise(noise, 0.1, 0.9), -std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace bouncecal::audio
