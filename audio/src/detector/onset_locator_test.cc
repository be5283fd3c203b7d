#include "detector/onset_locator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "detector/candidate_tracker.h"
#include "detector/stage_test_support.h"
#include "detector/test_signals.h"

namespace bouncecal::audio {
namespace {

std::vector<LocatedImpact> Locate(const std::vector<float>& x, int rate,
                                  const DetectorOptions& options = {}) {
  testing::StageRig rig(rate, options);
  SampleHistory<float> raw(static_cast<std::size_t>(2 * rate));
  raw.PushBlock(x);
  BandRiseNovelty band_rise(rig.bands);
  CandidateTracker tracker(rig.frames, options, rig.bands);
  OnsetLocator locator(rig.frames, options, rig.bands, rig.residual, raw);
  std::vector<LocatedImpact> located;
  rig.Run(x, [&](std::int64_t n, std::ptrdiff_t k) {
    tracker.TrackPeak(n);
    if (n - rig.frames.attack < rig.frames.lookback) return;
    const NoveltyRise residual = rig.residual.Rise(n, k, false);
    const NoveltyRise band = band_rise.Rise(n, k, tracker.WantsBandRise(residual));
    if (auto candidate = tracker.Step(n, k, band, residual)) {
      if (auto impact = locator.Locate(*candidate)) located.push_back(*impact);
    }
  });
  return located;
}

// Each true onset's located candidate: the one that rose most within 5 ms of it (the ringing of
// an impact may open later candidates, which the merger folds in).
std::vector<LocatedImpact> Nearest(const std::vector<LocatedImpact>& located,
                                   const std::vector<double>& onsets) {
  std::vector<LocatedImpact> nearest;
  for (double onset : onsets) {
    const LocatedImpact* best = nullptr;
    for (const auto& impact : located) {
      if (std::fabs(impact.impact.onset_s - onset) < 5e-3 &&
          (!best || impact.rise_db > best->rise_db)) {
        best = &impact;
      }
    }
    if (best) nearest.push_back(*best);
  }
  return nearest;
}

// An impact of the same shape at three levels, 40 dB apart at the extremes: its timing
// reference (12 % of its peak) lands at the same place on its edge, so the onset less the true
// onset is the same at every level to within the reference's stated sigma. (This signal is
// causal; tests/detector_ground_truth_test.cc does the same through a linear-phase recording
// chain, where a first-sample-out-of-the-noise picker fails.)
TEST(OnsetLocator, TheTimingReferenceDoesNotMoveWithLoudness) {
  constexpr int kRate = 48000;
  const std::vector<double> onsets = {0.3000, 0.5013, 0.7027};
  const double levels[] = {0.5, 0.05, 0.005};
  std::vector<float> x(kRate, 0.0f);
  testing::AddNoise(x, 2e-5, 12);
  for (int i = 0; i < 3; ++i) testing::AddImpact(x, kRate, onsets[i], levels[i]);
  const auto located = Nearest(Locate(x, kRate), onsets);
  ASSERT_EQ(located.size(), 3u);
  const double offset = located[0].impact.onset_s - onsets[0];
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(located[static_cast<std::size_t>(i)].by_reference) << i;
    EXPECT_NEAR(
        located[static_cast<std::size_t>(i)].impact.onset_s - onsets[static_cast<std::size_t>(i)],
        offset, 2 * located[static_cast<std::size_t>(i)].impact.onset_uncertainty_s)
        << i;
  }
  // The offset is a sample or two: the reference lies on the edge's first lobes.
  EXPECT_GE(offset, -1.0 / kRate);
  EXPECT_LE(offset, 3.0 / kRate);
}

// A hit that stands less than min_snr_db above the noise in every band is no impact.
TEST(OnsetLocator, AnImpactUnderTheSnrGateIsNotLocated) {
  constexpr int kRate = 48000;
  std::vector<float> x(kRate, 0.0f);
  testing::AddNoise(x, 1e-3, 2);
  testing::AddImpact(x, kRate, 0.5, 0.5);
  DetectorOptions strict;
  strict.min_snr_db = 80;
  EXPECT_TRUE(Locate(x, kRate, strict).empty());
  EXPECT_EQ(Nearest(Locate(x, kRate), {0.5}).size(), 1u);
}

TEST(ReferenceToContactOffset, IsTheMedianOfTheFittedLeadsOrZeroWithoutAny) {
  std::vector<LocatedImpact> impacts(4);
  impacts[0].reference_lead_s = 10e-6;
  impacts[1].reference_lead_s = 40e-6;
  impacts[2].reference_lead_s = 20e-6;
  EXPECT_DOUBLE_EQ(ReferenceToContactOffset(impacts), 20e-6);
  EXPECT_DOUBLE_EQ(ReferenceToContactOffset({LocatedImpact{}}), 0.0);
}

}  // namespace
}  // namespace bouncecal::audio
