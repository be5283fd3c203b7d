// The interval and the speed-trend test on recordings with real scatter, through the whole chain:
// a steel ball on copper (e = 0.65, 3 % per-impact scatter of e, 0.20 m) rendered by the
// synthesiser, detected, and calibrated with the true height, as in issue 29's recordings from
// an independent generator. bench/calibrate_chain_coverage_bench measures the full table
// (docs/calibration.md); this checks one row on fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/jittered_drop.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/error.h"
#include "bouncecal/random_stream.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal {
namespace {

using bouncecal::testing::ScratchPath;

constexpr double kGravity = 9.81;
constexpr double kRestitution = 0.65;
constexpr double kJitter = 0.03;
constexpr double kDropHeightM = 0.20;

// Ballistic flights with e_k = e (1 + jitter z_k) (by default 0.65 with 3 % from 0.20 m),
// rendered (plate modes, reverb, 35 dB noise), written as WAV and detected as `bouncecal
// calibrate` does.
calibrate::MeasuredSequence RecordDrop(std::uint64_t seed, double restitution = kRestitution,
                                       double jitter = kJitter,
                                       double drop_height_m = kDropHeightM) {
  RandomStream draws(seed, 0, 7);
  audio::SynthesisOptions synthesis;
  double onset = 0.3 + std::sqrt(2 * drop_height_m / kGravity);
  double speed = std::sqrt(2 * kGravity * drop_height_m);
  for (int k = 0; k < 60; ++k) {
    synthesis.impacts.push_back({onset, speed, 0});
    speed *= std::min(restitution * (1 + jitter * draws.Gaussian()), 0.999);
    const double flight = 2 * speed / kGravity;
    if (flight < 0.004) break;
    onset += flight;
  }
  synthesis.reverb = audio::ReverbOptions{};
  synthesis.noise = audio::NoiseOptions{};
  synthesis.seed = seed;
  const auto path = ScratchPath("chain_" + std::to_string(seed) + ".wav");
  audio::WriteRecording(path, audio::SynthesizeBounces(synthesis).channels);
  return calibrate::LoadSequences({path}).front();
}

calibrate::FitOptions WithHeight() {
  calibrate::FitOptions options;
  options.analytic_check = false;  // not part of the interval
  options.drop.drop_height_m = kDropHeightM;
  options.drop_height_given = true;
  return options;
}

// The fit of the scatter-free, noise-free drop whose e has the material's mean energy loss
// 1 - e^2 (1 + j^2): what averages over ever more impacts converge to.
double MaterialGamma() {
  calibrate::JitteredDropOptions ideal;
  ideal.drop_height_m = kDropHeightM;
  ideal.restitution = kRestitution * std::sqrt(1 + kJitter * kJitter);
  ideal.relative_jitter = 0;
  ideal.timing_sigma_s = 0;
  return calibrate::Fit({calibrate::JitteredDrop(ideal)}, WithHeight()).parameters[0].value;
}

// 24 seeds. Coverage: a correct 95 % interval covers at most 19 of 24 with probability 7e-3.
// Trend claims on these constant-e drops: a 1 % test makes 2 or more of 24 with probability
// 0.024. Collapse: the timing-only width is ~20 times below the scatter's (0.002 against ~0.04
// in issue 29, 0.03-0.08 of the median), whereas the posterior's width follows the scatter each
// recording shows: with the 3-5 degrees of freedom its precise impacts give tau, the smallest of
// 24 chi-square draws puts the narrowest interval near 0.25-0.45 of the median, so none may be
// narrower than 0.15 of it. Measured on these seeds: 21 of the 22 usable recordings covered, one
// trend claimed, the narrowest at 0.24 of the median (2 recordings are split by the audio stage).
TEST(CalibrateChainCoverage, ScatteredConstantRestitutionIsCoveredWithoutFalseTrends) {
  const double truth = MaterialGamma();
  int covered = 0, trends = 0, fits = 0, unusable = 0;
  std::vector<double> widths;
  for (std::uint64_t seed = 100; seed < 124; ++seed) {
    calibrate::FitSummary summary;
    try {
      summary = calibrate::Fit({RecordDrop(seed)}, WithHeight());
    } catch (const Error&) {
      // The audio stage sometimes splits a drop so that fewer than 4 onsets stay together (it
      // says so): a question for the detector's tests, not for the interval.
      ++unusable;
      continue;
    }
    const auto& interval = summary.parameters[0].confidence_interval;
    ASSERT_TRUE(interval) << summary.uncertainty.message;
    ++fits;
    covered += interval->first <= truth && truth <= interval->second ? 1 : 0;
    trends += summary.adequacy.trend ? 1 : 0;
    widths.push_back(interval->second - interval->first);
  }
  RecordProperty("covered", covered);
  RecordProperty("unusable", unusable);
  ASSERT_GE(fits, 20) << unusable << " recordings could not be calibrated";
  RecordProperty("trends", trends);
  std::sort(widths.begin(), widths.end());
  const double median = widths[widths.size() / 2];
  RecordProperty("narrowest_over_median_percent", static_cast<int>(100 * widths.front() / median));
  EXPECT_GE(covered, 20) << covered << " of " << fits;
  EXPECT_LE(trends, 1) << trends << " of " << fits;
  EXPECT_GE(widths.front(), 0.15 * median) << "median width " << median;
}

// Five recordings of a steel ball on an anvil (e = 0.8, no scatter, 0.35 m, seeds first_seed to
// first_seed + 4) fitted jointly, with or without their height.
calibrate::FitSummary FitFiveAnvilRecordings(std::uint64_t first_seed, bool with_height) {
  std::vector<calibrate::MeasuredSequence> recordings;
  for (std::uint64_t r = 0; r < 5; ++r)
    recordings.push_back(RecordDrop(first_seed + r, 0.8, 0, 0.35));
  calibrate::FitOptions options;
  options.analytic_check = false;
  if (with_height) {
    options.drop.drop_height_m = 0.35;
    options.drop_height_given = true;
  }
  return calibrate::Fit(recordings, options);
}

// Each set's ~50 impacts make the trend test sensitive to eta_k changes of a few 1e-4. Expects no
// trend claim in any set.
void ExpectNoTrendInFiveAnvilRecordings(std::uint64_t first_seed, int sets, bool with_height) {
  int trends = 0;
  for (int set = 0; set < sets; ++set) {
    const auto summary = FitFiveAnvilRecordings(first_seed + 5 * set, with_height);
    ASSERT_TRUE(summary.adequacy.tested) << summary.adequacy.message;
    trends += summary.adequacy.trend ? 1 : 0;
    EXPECT_FALSE(summary.adequacy.trend) << "set " << set << ": " << summary.adequacy.message;
  }
  ::testing::Test::RecordProperty("trends", trends);
}

// Onsets timed from the whole response lock on the contact's centroid, which drifts with the
// contact's duration through a drop; uncorrected, that drift claimed a trend on 199 of 200 such
// sets (reverted in 6a3f48a), corrected none (docs/detector.md, "The contact's centroid"). A 1 %
// test claims none of these 4 sets with probability 0.96; these seeds claim none.
TEST(CalibrateChainCoverage, FiveAnvilRecordingsWithoutScatterClaimNoSpeedTrend) {
  ExpectNoTrendInFiveAnvilRecordings(200, 4, /*with_height=*/false);
}

// With their true height the first eta_k comes from the height and the first interval, which
// holds the DEM drop's contact (68 us) and not the synthesiser's, so the fitted drop's eta_k run
// from 0.35990 to 0.36014 while the measured ones stay within 1e-5 of 0.36. That is the contact's
// duration, not a damping trend: the test has it as a nuisance (model_adequacy.h). Without it,
// 200 of 200 such fits claimed a trend on the chain bench, and both sets here.
TEST(CalibrateChainCoverage, FiveAnvilRecordingsWithoutScatterAndTheirHeightClaimNoSpeedTrend) {
  ExpectNoTrendInFiveAnvilRecordings(300, 2, /*with_height=*/true);
}

// Without scatter the interval is the timing noise's. The per-impact scatter's posterior cannot
// exclude a tau_w as large as the timing noise from these ~50 impacts, so its part of the
// interval's variance stays comparable to timing's (0.26-0.34 on these sets), but the simulated
// drop's contact is a smooth pattern in k, not scatter: read as scatter (before it entered the
// scatter's model as the trend test's nuisance) it took tau_w to 7e-5-8e-5 in eta and 0.94-0.99
// of the variance in three of these four sets, at 3-7x the width (docs/calibration.md). Below
// 0.6 in every set separates the two with room on both sides.
TEST(CalibrateChainCoverage, FiveAnvilRecordingsWithoutScatterGetAnIntervalOfTheirTimingNoise) {
  for (std::uint64_t set = 0; set < 4; ++set) {
    const bool with_height = set % 2 == 0;
    const auto summary = FitFiveAnvilRecordings(400 + 5 * set, with_height);
    ASSERT_TRUE(summary.uncertainty.available) << summary.uncertainty.message;
    EXPECT_LT(summary.uncertainty.scatter_share, 0.6)
        << "set " << set << (with_height ? " with" : " without") << " the height: tau_w "
        << summary.uncertainty.per_impact_scatter;
  }
}

}  // namespace
}  // namespace bouncecal
