// Onset timing and recall of the impact detector against synthetic recordings with known
// onsets (audio::SynthesizeBounces), across the conditions real recordings bring. Each test
// prints its figures so the measured numbers can be quoted (docs/recordings.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <tuple>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/detect_file.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/response_timing.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::audio {
namespace {

using bouncecal::testing::ScratchPath;

struct Score {
  int truth = 0;
  int found = 0;  // truth impacts with a detection within kMatchS
  int extra = 0;  // detections near no truth impact
  // The recording's constant offset: the median signed error. Onsets are timed by a reference
  // on each impact's edge and brought back to the start of contact by one offset per recording
  // (onset_locator.h), which cancels in every interval.
  double offset_s = 0;
  double median_abs_error_s = 0;  // less the offset
  double p90_abs_error_s = 0;     // less the offset
  // |detected - true| of the intervals between consecutive truth impacts both found: what e_k
  // and eta_k are made of.
  double interval_median_s = 0;
  double interval_p95_s = 0;
  int within_two_sigma = 0;      // found impacts with |error - offset| <= 2 onset_uncertainty_s
  std::vector<double> sigmas_s;  // onset_uncertainty_s of the found impacts
};

// A detection belongs to a truth impact if it is within 1 ms: far below the shortest flight
// the tests use (30 ms) and far above any onset error.
constexpr double kMatchS = 1e-3;

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()))];
}

Score Compare(const std::vector<Impact>& detected, const std::vector<double>& truth_s) {
  Score score;
  score.truth = static_cast<int>(truth_s.size());
  std::vector<double> errors;  // per truth impact, NaN when not found
  std::vector<double> sigmas;
  for (double t : truth_s) {
    double best = 1e9;
    double sigma = 0;
    for (const auto& impact : detected) {
      if (std::fabs(impact.onset_s - t) < std::fabs(best)) {
        best = impact.onset_s - t;
        sigma = impact.onset_uncertainty_s;
      }
    }
    errors.push_back(std::fabs(best) < kMatchS ? best : std::nan(""));
    sigmas.push_back(sigma);
  }
  for (const auto& impact : detected) {
    bool near = false;
    for (double t : truth_s) near = near || std::fabs(impact.onset_s - t) < kMatchS;
    if (!near) ++score.extra;
  }
  std::vector<double> found_errors;
  std::vector<double> intervals;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (std::isnan(errors[k])) continue;
    found_errors.push_back(errors[k]);
    if (k > 0 && !std::isnan(errors[k - 1]))
      intervals.push_back(std::fabs(errors[k] - errors[k - 1]));
  }
  score.found = static_cast<int>(found_errors.size());
  if (found_errors.empty()) return score;
  score.offset_s = Quantile(found_errors, 0.5);
  std::vector<double> centred;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (std::isnan(errors[k])) continue;
    centred.push_back(std::fabs(errors[k] - score.offset_s));
    score.sigmas_s.push_back(sigmas[k]);
    if (centred.back() <= 2 * sigmas[k]) ++score.within_two_sigma;
  }
  score.median_abs_error_s = Quantile(centred, 0.5);
  score.p90_abs_error_s = Quantile(centred, 0.9);
  score.interval_median_s = Quantile(intervals, 0.5);
  score.interval_p95_s = Quantile(intervals, 0.95);
  return score;
}

void Print(const std::string& condition, const Score& s) {
  std::printf(
      "[ figures  ] %-28s recall %2d/%2d  extra %2d  offset %+6.1f us  |error - offset| median "
      "%5.1f p90 %6.1f us  interval error median %5.1f p95 %6.1f us\n",
      condition.c_str(), s.found, s.truth, s.extra, s.offset_s * 1e6, s.median_abs_error_s * 1e6,
      s.p90_abs_error_s * 1e6, s.interval_median_s * 1e6, s.interval_p95_s * 1e6);
}

// The reference scene: a steel ball (e = 0.8) dropped from 0.3 m on a steel plate whose modes
// ring for tens of ms (a plate resting on a table), 48 kHz. The drop stops at 30 ms flights:
// below that the sources find the ball chattering, and the detector is not asked for it.
// Noise is referred to the weakest impact, so "10 dB" means every impact is 10 dB above it.
SynthesisOptions Reference(double snr_db = 40.0) {
  SynthesisOptions options;
  options.drop.drop_height_m = 0.3;
  options.drop.restitution.constant = 0.8;
  options.drop.min_flight_s = 0.03;
  for (auto& mode : options.modes) mode.decay_s *= 0.1;
  NoiseOptions noise;
  noise.snr_db = snr_db;
  noise.reference = SnrReference::kWeakestImpact;
  options.noise = noise;
  options.seed = 17;
  return options;
}

// The detector's impacts with the tentative ones that continue a bounce sequence adopted, as
// bouncecal analyze sees them.
DetectionResult Detect(const Recording& recording, const DetectorOptions& options = {}) {
  auto detection = DetectImpacts(recording, options);
  GroupBounces(detection);
  return detection;
}

Score Evaluate(const std::string& condition, const SynthesisOptions& options) {
  const auto synthesized = SynthesizeBounces(options);
  const auto detection = Detect(synthesized.channels[0]);
  const auto score = Compare(detection.impacts, synthesized.BallImpactOnsetsS());
  Print(condition, score);
  return score;
}

// Intervals are what e_k and eta_k are made of, so they carry the targets (issue 16): at 48 kHz
// a median interval error of at most 20 us and a 95th percentile of at most 100 us on clean
// recordings. Onsets are timed where each impact's edge reaches 12 % of its peak
// (constant-fraction timing, onset_picker.h) and moved back to the start of contact by one offset
// per recording; that offset (the median signed error) stays within 2 samples (42 us). Measured
// with this seed: interval error median 2.8 / 1.9 / 1.9 / 4.0 / 4.4 us and p95 39 / 38 / 38 / 37
// / 47 us at 40 / 30 / 20 / 15 / 10 dB; offsets +12, +34, +6, +7, -3 us. Below 30 dB the p95
// bound is the noisy 50 us target doubled, as for the clean one.
constexpr double kIntervalMedianS = 20e-6;
constexpr double kIntervalP95S = 100e-6;
constexpr double kOffsetS = 2.0 / 48000;

TEST(DetectorGroundTruth, TimingAndRecallAcrossSnr) {
  for (double snr_db : {40.0, 30.0, 20.0, 15.0, 10.0}) {
    const auto score =
        Evaluate("snr " + std::to_string(static_cast<int>(snr_db)) + " dB", Reference(snr_db));
    // Every impact is found at >= 30 dB. Below, the last impact (the weakest one, which the
    // SNR refers to, 30 ms after the one before) may fall under the thresholds: one may be lost.
    EXPECT_GE(score.found, snr_db >= 30 ? score.truth : score.truth - 1) << snr_db;
    EXPECT_LE(score.extra, 1) << snr_db;
    EXPECT_LT(score.interval_median_s, kIntervalMedianS) << snr_db;
    EXPECT_LT(score.interval_p95_s, kIntervalP95S) << snr_db;
    EXPECT_LT(std::fabs(score.offset_s), kOffsetS) << snr_db;
  }
}

// The stated onset uncertainty must be honest for what enters an interval: the error less the
// recording's constant offset. Pooled over seeds 17 and 1-4 (65 impacts per SNR, so one impact
// moves the fraction by 1.5 %). Coverage: at every SNR at least 85 % of the found impacts lie
// within 2 sigma (95 % for exact Gaussian errors); measured 100, 100, 97, 92 % at 40, 30, 20,
// 10 dB (the shape term of the reference crossing, onset_picker.cc, is set from
// bench/detector_accuracy_bench); 85 % is one binomial standard deviation (3.4 %) below the
// lowest, and another for margin. Inflation: the median sigma at 40 dB stays within 2 samples
// (42 us), the spread that one lobe more or less before the crossing gives; measured 36 us.
TEST(DetectorGroundTruth, OnsetUncertaintyCoversTheErrorAtEverySnr) {
  constexpr double kMinCoverage = 0.85;
  constexpr double kCleanMedianSigmaS = 2.0 / 48000;
  for (double snr_db : {40.0, 30.0, 20.0, 10.0}) {
    int found = 0;
    int covered = 0;
    std::vector<double> sigmas_s;
    for (unsigned seed : {17u, 1u, 2u, 3u, 4u}) {
      auto options = Reference(snr_db);
      options.seed = seed;
      const auto synthesized = SynthesizeBounces(options);
      const auto detection = Detect(synthesized.channels[0]);
      const auto score = Compare(detection.impacts, synthesized.BallImpactOnsetsS());
      std::printf("[ figures  ] snr %2.0f dB seed %2u  within 2 sigma %2d/%2d\n", snr_db, seed,
                  score.within_two_sigma, score.found);
      found += score.found;
      covered += score.within_two_sigma;
      sigmas_s.insert(sigmas_s.end(), score.sigmas_s.begin(), score.sigmas_s.end());
    }
    ASSERT_GT(found, 0) << snr_db;
    std::sort(sigmas_s.begin(), sigmas_s.end());
    const double median_sigma_s = sigmas_s[sigmas_s.size() / 2];
    const double coverage = static_cast<double>(covered) / found;
    std::printf(
        "[ figures  ] snr %2.0f dB  within 2 sigma %2d/%2d (%.0f %%)  median sigma %.1f us\n",
        snr_db, covered, found, 100 * coverage, median_sigma_s * 1e6);
    EXPECT_GE(coverage, kMinCoverage) << snr_db;
    if (snr_db >= 40) {
      EXPECT_LE(median_sigma_s, kCleanMedianSigmaS);
    }
  }
}

// The picker must not be tuned to one contact: a 40 us (hard, small ball) and a 150 us (softer)
// contact, and a drop from 0.8 m with e = 0.6, held to the interval targets (above) at 40 dB and
// to 50 us median at 10 dB. Measured interval error medians 1.7, 2.2, 8.1 us at 40 dB and 6.7,
// 11.7, 19.0 us at 10 dB; p95 24, 29, 38 and 36, 58, 52 us.
TEST(DetectorGroundTruth, TimingHoldsForOtherContactDurationsAndDrops) {
  for (double snr_db : {40.0, 10.0}) {
    auto short_contact = Reference(snr_db);
    short_contact.contact_duration_s = 40e-6;
    auto long_contact = Reference(snr_db);
    long_contact.contact_duration_s = 150e-6;
    auto other_drop = Reference(snr_db);
    other_drop.drop.drop_height_m = 0.8;
    other_drop.drop.restitution.constant = 0.6;
    const std::string snr = " at " + std::to_string(static_cast<int>(snr_db)) + " dB";
    for (const auto& [name, options, clean_bound_s, noisy_bound_s] :
         std::vector<std::tuple<std::string, SynthesisOptions, double, double>>{
             {"contact 40 us" + snr, short_contact, kIntervalMedianS, 50e-6},
             {"contact 150 us" + snr, long_contact, kIntervalMedianS, 50e-6},
             {"h 0.8 m, e 0.6" + snr, other_drop, kIntervalMedianS, 50e-6}}) {
      const auto score = Evaluate(name, options);
      EXPECT_GE(score.found, score.truth - (snr_db >= 30 ? 0 : 2)) << name;
      EXPECT_EQ(score.extra, 0) << name;
      EXPECT_LT(score.interval_median_s, snr_db >= 40 ? clean_bound_s : noisy_bound_s) << name;
      EXPECT_LT(score.interval_p95_s, kIntervalP95S) << name;
    }
  }
}

TEST(DetectorGroundTruth, SampleRatesFrom16To96kHz) {
  for (int rate : {16000, 44100, 48000, 96000}) {
    auto options = Reference();
    options.sample_rate_hz = rate;
    const auto score = Evaluate(std::to_string(rate) + " Hz", options);
    EXPECT_EQ(score.found, score.truth) << rate;
    EXPECT_EQ(score.extra, 0) << rate;
    // At 16 kHz the edge is a sample or two long: the 16 kHz target is a p95 of 200 us,
    // and one sample (62.5 us) bounds the median (measured 61 and 114 us). Measured medians
    // 1.6, 2.8 and 0.9 us and p95 40, 39 and 38 us at 44.1, 48 and 96 kHz.
    EXPECT_LT(score.interval_median_s, rate >= 44100 ? kIntervalMedianS : 1.0 / rate) << rate;
    EXPECT_LT(score.interval_p95_s, rate >= 44100 ? kIntervalP95S : 200e-6) << rate;
  }
}

TEST(DetectorGroundTruth, ReverbEchoesPrecursorsClippingHumAndDc) {
  auto reverb = Reference();
  reverb.reverb = ReverbOptions{};
  reverb.reverb->echoes = {Echo{0.009, -12.0}};
  auto precursor = Reference();
  precursor.precursor = PrecursorOptions{};
  auto clipped = Reference();
  clipped.clip_level = 0.2;
  auto hum = Reference();
  hum.hum = HumOptions{50.0, -20.0, 5};
  hum.dc_offset = 0.2;
  for (const auto& [name, options] :
       std::vector<std::pair<std::string, SynthesisOptions>>{{"reverb + 9 ms echo", reverb},
                                                             {"precursor 7 ms", precursor},
                                                             {"clipped at 0.2", clipped},
                                                             {"hum -20 dBFS + DC", hum}}) {
    const auto score = Evaluate(name, options);
    EXPECT_EQ(score.found, score.truth) << name;
    EXPECT_EQ(score.extra, 0) << name;
    // Clipping flattens the first peak and reverb fills the gap before an onset; intervals hold
    // the clean targets (measured medians 3.0, 1.5, 2.8, 1.5 us and p95 36, 5, 44, 11 us for
    // reverb, precursor, clipping and hum).
    EXPECT_LT(score.interval_median_s, kIntervalMedianS) << name;
    EXPECT_LT(score.interval_p95_s, kIntervalP95S) << name;
  }
}

TEST(DetectorGroundTruth, KnockAndThumpsAreNotPartOfTheSequence) {
  auto options = Reference();
  options.drop.release_s = 1.0;
  options.extra_events = {{SoundEventKind::kKnock, 0.3, 0.3},
                          {SoundEventKind::kThump, 0.6, 0.4},
                          {SoundEventKind::kThump, 3.5, 0.4}};
  const auto synthesized = SynthesizeBounces(options);
  const auto detection = Detect(synthesized.channels[0]);
  const auto truth = synthesized.BallImpactOnsetsS();
  const auto score = Compare(detection.impacts, truth);
  Print("knock + thumps", score);
  EXPECT_EQ(score.found, score.truth);
  const auto grouping = FindBounceSequences(detection.impacts);
  ASSERT_EQ(grouping.sequences.size(), 1u);
  const auto& members = grouping.sequences[0].impact_indices;
  // The sequence starts at the first ball impact, not at the knock 0.9 s before it.
  EXPECT_NEAR(detection.impacts[static_cast<size_t>(members.front())].onset_s, truth.front(),
              kMatchS);
  EXPECT_GE(members.size(), truth.size() - 1);
}

TEST(DetectorGroundTruth, SeveralDropsGiveSeveralSequences) {
  auto options = Reference();
  options.drop.drop_count = 3;
  options.drop.gap_between_drops_s = 1.0;
  const auto synthesized = SynthesizeBounces(options);
  const auto detection = Detect(synthesized.channels[0]);
  const auto score = Compare(detection.impacts, synthesized.BallImpactOnsetsS());
  Print("3 drops", score);
  EXPECT_EQ(score.found, score.truth);
  const auto grouping = FindBounceSequences(detection.impacts);
  ASSERT_EQ(grouping.sequences.size(), 3u);
  for (int drop = 0; drop < 3; ++drop) {
    const auto truth = synthesized.BallImpactOnsetsS(drop);
    const auto first = grouping.sequences[static_cast<size_t>(drop)].impact_indices.front();
    EXPECT_NEAR(detection.impacts[static_cast<size_t>(first)].onset_s, truth.front(), kMatchS);
  }
}

// Stereo files are read, never averaged: the channel with the better impact-to-noise ratio
// is chosen and its own (delayed) onsets come out. Written as 24-bit and float WAV.
TEST(DetectorGroundTruth, StereoPicksTheBetterChannelIn24BitAndFloatFiles) {
  auto options = Reference(30.0);
  options.channels = {ChannelOptions{0.0, -6.0, -15.0},    // quieter and noisier
                      ChannelOptions{0.25e-3, 0.0, 0.0}};  // 0.25 ms later, cleaner
  const auto synthesized = SynthesizeBounces(options);
  std::vector<double> truth;
  for (double t : synthesized.BallImpactOnsetsS()) truth.push_back(t + 0.25e-3);
  for (auto encoding : {SampleEncoding::kPcm24, SampleEncoding::kFloat}) {
    const auto path = ScratchPath("stereo_" + std::string(ToString(encoding)) + ".wav");
    WriteRecording(path, synthesized.channels, {AudioContainer::kWav, encoding});
    const auto detection = AnalyzeBounces(path).detection;
    EXPECT_EQ(detection.channel, 1);
    EXPECT_TRUE(detection.channel_chosen_automatically);
    const auto score = Compare(detection.detection.impacts, truth);
    Print("stereo " + std::string(ToString(encoding)), score);
    EXPECT_EQ(score.found, score.truth);
    EXPECT_LT(score.interval_median_s, kIntervalMedianS);
  }
}

// The detector suite's rubber ball (an independent generator's, exact truth; by path, skipped
// where absent): its 11th bounce (1.3 ms contact, 4.6 dB over the tail before it) is heard only in
// the ringing and picked on the prediction innovation, whose largest sample lies 1.3 ms into the
// contact; cut there, the change point fell on it (1.31 ms late at a stated 4.9 ms, and the
// scorer's 1 ms matching counted it a false alarm). With 1 ms more of the burst
// (PickOnsetInInnovation) it is where contact began, within 0.3 ms: the AIC's spread for a step of
// a few dB (onset_picker_test.cc: a median 13.4 samples, 0.28 ms; here 0.02 ms).
TEST(DetectorGroundTruth, ASoftBallsBounceInRingingIsPickedWhereItsInnovationBegins) {
  const auto folder = testing::SharedDir() / "detector-suite" / "recordings";
  const auto wav = folder / "rubber_ball.wav";
  if (!std::filesystem::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  std::ifstream truth_file(folder / "rubber_ball.json");
  const auto truth = nlohmann::json::parse(truth_file)["impact_times_s"].get<std::vector<double>>();
  ASSERT_GT(truth.size(), 10u);
  const auto result = DetectImpactsInFile(wav.string(), {});
  const Impact* nearest = nullptr;
  for (const auto* impacts : {&result.detection.impacts, &result.detection.tentative}) {
    for (const Impact& impact : *impacts) {
      if (!nearest ||
          std::fabs(impact.onset_s - truth[10]) < std::fabs(nearest->onset_s - truth[10])) {
        nearest = &impact;
      }
    }
  }
  ASSERT_NE(nearest, nullptr);
  EXPECT_TRUE(nearest->residual_only);
  EXPECT_NEAR(nearest->onset_s, truth[10], 0.3e-3);
}

}  // namespace
}  // namespace bouncecal::audio

namespace bouncecal::audio {
namespace {

// A drop on a free plate (rings for its whole flight), e constant, 30 dB over the weakest impact.
SynthesisOptions FreePlateDrop(double e, std::uint64_t seed) {
  SynthesisOptions options;
  options.drop.restitution.constant = e;
  options.drop.min_flight_s = 0.03;
  NoiseOptions noise;
  noise.snr_db = 30.0;
  noise.reference = SnrReference::kWeakestImpact;
  options.noise = noise;
  options.seed = seed;
  return options;
}

// The paper's own setup: a steel ball dropped 20 cm on a free steel plate whose modes ring for
// up to 1.7 s (the synthesiser's default SteelPlateModes). From the third or fourth bounce on,
// each impact is quieter than the tail of the earlier ones in every band, so only the ringing
// residual (bins that rise above their own recent maxima, averaged in dB) finds them; the onset
// is then picked on the linear-prediction innovation. e from 0.5 to 0.9, three seeds each,
// 30 dB SNR referred to the weakest impact.
TEST(DetectorGroundTruth, ImpactsInsideALongRingingFreePlateAreFound) {
  int truth = 0;
  int found = 0;
  int extra = 0;
  std::vector<double> errors;
  for (double e : {0.5, 0.65, 0.8, 0.9}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const auto synthesized = SynthesizeBounces(FreePlateDrop(e, seed));
      const auto detection = Detect(synthesized.channels[0]);
      const auto onsets = synthesized.BallImpactOnsetsS();
      const auto score = Compare(detection.impacts, onsets);
      Print("free plate e " + std::to_string(e).substr(0, 4) + " seed " + std::to_string(seed),
            score);
      truth += score.truth;
      found += score.found;
      extra += score.extra;
      for (double t : onsets) {
        for (const auto& impact : detection.impacts) {
          if (std::fabs(impact.onset_s - t) < kMatchS)
            errors.push_back(std::fabs(impact.onset_s - t));
        }
      }
    }
  }
  std::sort(errors.begin(), errors.end());
  ASSERT_FALSE(errors.empty());
  const double median = errors[errors.size() / 2];
  const double p90 = errors[std::min(errors.size() - 1, errors.size() * 9 / 10)];
  std::printf(
      "[ figures  ] free plate, all: recall %d/%d  extra %d  |error| median %.1f us  p90 %.1f us\n",
      found, truth, extra, median * 1e6, p90 * 1e6);
  // The synthesiser's Kirchhoff plate packs 61 modes 220 Hz apart; the earlier complex-domain
  // residual (one tone per bin) found 87/144 on it, the per-bin novelty finds 139/144 with 2
  // extras, both late bounces adopted 1-1.5 ms off (measured). The target: at least 93 %
  // found, at most 3 % extras. The misses are the last one or two impacts of some drops, 30-40 ms
  // after the previous one and 20-25 dB under the tail.
  EXPECT_GE(found, truth * 93 / 100);
  EXPECT_LE(extra, truth * 3 / 100);
  // Inside ringing the onsets come late (+40 us signed median: the modes' t^3 growth during
  // contact takes long to emerge from the tail); measured 42.3 us median with the power-law
  // picker. The 50 us bound (its 10 dB SNR target; this plate is 30 dB SNR but its tail
  // buries later impacts far deeper) holds.
  EXPECT_LT(median, 50e-6);
}

}  // namespace
}  // namespace bouncecal::audio

namespace bouncecal::audio {
namespace {

// The same plate at 16 kHz through a linear-phase recording chain (a phone or a resampled file;
// the detector suite's sr16000 has an impact like these). An impact in the tail is picked on the
// prediction innovation, whose predictor needs four samples per coefficient at least: the 4 ms
// before the search held 64 samples at 16 kHz, under the 96 its 24 coefficients need, so the
// innovation was skipped and the onset picked on the tail itself (measured over these 12 drops:
// recall 108/144 with 43 extras then, 137/144 with 14 extras once the fit spans at least 8
// samples per coefficient, as 4 ms do at 48 kHz). Bounds about halfway between, so a detector
// that skips the innovation again fails: at least 85 % found, at most 20 % extras.
TEST(DetectorGroundTruth, AtSixteenKilohertzImpactsInsideAFreePlatesRingingAreFound) {
  int truth = 0;
  int found = 0;
  int extra = 0;
  for (double e : {0.5, 0.65, 0.8, 0.9}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      SynthesisOptions options = FreePlateDrop(e, seed);
      options.sample_rate_hz = 16000;
      options.chain = RecordingChain{};
      options.click_gain = 0.2;
      const auto synthesized = SynthesizeBounces(options);
      const auto score =
          Compare(Detect(synthesized.channels[0]).impacts, synthesized.BallImpactOnsetsS());
      Print(
          "free plate 16 kHz e " + std::to_string(e).substr(0, 4) + " seed " + std::to_string(seed),
          score);
      truth += score.truth;
      found += score.found;
      extra += score.extra;
    }
  }
  std::printf("[ figures  ] free plate 16 kHz, chain, all: recall %d/%d  extra %d\n", found, truth,
              extra);
  EXPECT_GE(found, truth * 85 / 100);
  EXPECT_LE(extra, truth * 20 / 100);
}

// A phone path or codec that cut the spectrum at 6.4 kHz of a 22.05 kHz recording (a counter's
// dense modes, 3 dB level jitter, pink noise 45 dB under the first impact, 6 seeds): a third of
// the ringing residual's bins held only the cut's stop band, where the lower quartile it takes
// for the noise under the ringing lay 70 dB under the real noise, so every sound in a tail passed
// the gate against it, and the 6 kHz band, a 0.4 kHz sliver of content, opened candidates whose
// onsets the low-pass's pre-ringing put early. Measured: 184 extra detections and 63 of the 93
// impacts found before, 79 (7-24 per seed) and 70 with the noise read below the content edge
// and the sliver band unused (the same scene without the cut: 83 found, 3 extra; what the
// cut's pre-ringing still does to the timing, 80-220 us median error against 50 us uncut, is
// left: docs/detector.md).
TEST(DetectorGroundTruth, ACutSpectrumIsNotReadAsNoiseNorItsSliverBandAsImpacts) {
  int truth = 0;
  int found = 0;
  int extra = 0;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
    SynthesisOptions options;
    options.sample_rate_hz = 22050;
    options.modes = CounterTopModes();
    options.contact_duration_s = 70e-6;
    options.drop.drop_height_m = 0.15 + 0.05 * static_cast<double>(seed);
    options.drop.restitution.constant = 0.75 + 0.02 * static_cast<double>(seed);
    options.drop.min_flight_s = 0.03;
    options.level_jitter_db = 3;
    options.band_limit_hz = 6400.0;
    NoiseOptions noise;
    noise.snr_db = 45;
    noise.color = NoiseColor::kPink;
    options.noise = noise;
    options.seed = seed;
    const auto synthesized = SynthesizeBounces(options);
    const auto score =
        Compare(Detect(synthesized.channels[0]).impacts, synthesized.BallImpactOnsetsS());
    Print("22.05 kHz cut at 6.4 kHz seed " + std::to_string(seed), score);
    truth += score.truth;
    found += score.found;
    extra += score.extra;
  }
  EXPECT_GE(found, truth * 70 / 100);
  EXPECT_LE(extra, truth);
}

// Band rises alone lose the bounces buried in the free plate's tail (measured 4 of 7 at
// e = 0.65); the ringing residual finds all but the last, weakest one (6 of 7).
TEST(DetectorGroundTruth, WithoutTheRingingResidualTheBuriedImpactsAreLost) {
  SynthesisOptions options;
  options.drop.restitution.constant = 0.65;
  options.drop.min_flight_s = 0.03;
  NoiseOptions noise;
  noise.snr_db = 30.0;
  noise.reference = SnrReference::kWeakestImpact;
  options.noise = noise;
  const auto synthesized = SynthesizeBounces(options);
  const auto truth = synthesized.BallImpactOnsetsS();
  DetectorOptions off;
  off.ringing_residual = false;
  const auto without = Compare(Detect(synthesized.channels[0], off).impacts, truth);
  const auto with = Compare(Detect(synthesized.channels[0]).impacts, truth);
  Print("free plate, residual off", without);
  Print("free plate, residual on", with);
  EXPECT_LE(without.found, without.truth - 3);
  EXPECT_GE(with.found, with.truth - 1);
}

}  // namespace
}  // namespace bouncecal::audio

namespace bouncecal::audio {
namespace {

// A lossy ball (e = 0.3, a steel ball on lead) dropped from 0.5 m makes two or three audible
// impacts. With the drop height the first flight dt_0 = 2 sqrt(2 h0 / g) is known, so they
// form a short sequence (issue 16) whose e_1 = dt_1 / dt_0 is the material's: checked within
// 0.01 (the first flight of 0.19 s is timed to tens of us, 2e-4 in e; contact time and the
// synthesiser's ballistic flights add nothing). Without the height the two impacts give no
// ratio. Over 6 seeds (drop heights 0.4-0.6 m, levels 0.3-0.8 of full scale).
TEST(DetectorGroundTruth, ALossyBallFormsAShortSequenceWithTheDropHeight) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    SynthesisOptions options;
    options.seed = seed;
    options.drop.drop_height_m = 0.4 + 0.04 * static_cast<double>(seed - 1);
    options.drop.restitution.constant = 0.3;
    options.drop.min_flight_s = 0.03;
    options.peak_amplitude = 0.3 + 0.1 * static_cast<double>(seed - 1);
    for (auto& mode : options.modes) mode.decay_s *= 0.1;
    NoiseOptions noise;
    noise.snr_db = 35;
    options.noise = noise;
    const auto synthesized = SynthesizeBounces(options);
    const double release_flight_s =
        2 * std::sqrt(2 * options.drop.drop_height_m / options.gravity_mps2);
    SequenceOptions sequences;
    sequences.release_flight_s = release_flight_s;
    auto detection = DetectImpacts(synthesized.channels[0]);
    auto without = detection;
    const auto grouping = GroupBounces(detection, sequences);
    ASSERT_EQ(grouping.sequences.size(), 1u) << seed;
    const auto& sequence = grouping.sequences[0];
    EXPECT_TRUE(sequence.short_sequence) << seed;
    ASSERT_GE(sequence.impact_indices.size(), 2u) << seed;
    const double dt1 = detection.impacts[static_cast<size_t>(sequence.impact_indices[1])].onset_s -
                       detection.impacts[static_cast<size_t>(sequence.impact_indices[0])].onset_s;
    EXPECT_NEAR(dt1 / release_flight_s, 0.3, 0.01) << seed;
    if (sequence.impact_indices.size() == 2) {
      EXPECT_TRUE(GroupBounces(without).sequences.empty()) << seed;
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio

namespace bouncecal::audio {
namespace {

// A real recording chain (issue 16): the sound rendered at 384 kHz and decimated by a
// linear-phase anti-aliasing filter spreads every click's energy a few samples BEFORE contact,
// the more the louder the impact (at 16 kHz the first impact's energy passes 1 % of its peak
// ~0.4 ms early, docs/synthesis.md). A picker that takes the first sample out of the noise
// then times the loud first impacts early and the quiet late ones late: measured with the
// detector before constant-fraction timing, the first impact's error minus the third's was
// -697 us at 16 kHz (median of 6 drops) and intervals were off by 869 us at p95. Timed where
// each edge reaches 12 % of its peak, the error must not depend on loudness: the first
// impact's error stays within 2 stated sigmas (combined) of the quietest matched impact's, and
// the intervals hold the 16 kHz target (p95 <= 200 us) and, at 48 kHz, its clean one
// (median <= 20 us, p95 <= 100 us). Measured over these 6 seeds: p95 90 us (16 kHz) and 41 us
// (48 kHz) in bench/detector_accuracy_bench's runs of 12.
TEST(DetectorGroundTruth, OnsetsThroughALinearPhaseChainDoNotDependOnLoudness) {
  for (int rate : {16000, 48000}) {
    std::vector<double> intervals;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      auto options = Reference(30.0);
      options.seed = seed;
      options.sample_rate_hz = rate;
      options.chain = RecordingChain{};
      options.click_gain = 0.2;
      options.contact_duration_s = 35e-6;
      options.drop.drop_height_m = 0.2 + 0.05 * static_cast<double>(seed);
      const auto synthesized = SynthesizeBounces(options);
      auto detection = DetectImpacts(synthesized.channels[0]);
      GroupBounces(detection);
      const auto truth = synthesized.BallImpactOnsetsS();
      std::vector<double> errors, sigmas;
      for (double t : truth) {
        double best = 1e9, sigma = 0;
        for (const auto& impact : detection.impacts) {
          if (std::fabs(impact.onset_s - t) < std::fabs(best)) {
            best = impact.onset_s - t;
            sigma = impact.onset_uncertainty_s;
          }
        }
        errors.push_back(std::fabs(best) < kMatchS ? best : std::nan(""));
        sigmas.push_back(sigma);
      }
      ASSERT_FALSE(std::isnan(errors.front())) << rate << " seed " << seed;
      std::size_t quiet = errors.size() - 1;
      while (quiet > 0 && std::isnan(errors[quiet])) --quiet;
      ASSERT_GT(quiet, 2u) << rate << " seed " << seed;
      EXPECT_LE(std::fabs(errors.front() - errors[quiet]),
                2 * std::hypot(sigmas.front(), sigmas[quiet]))
          << rate << " seed " << seed;
      for (std::size_t k = 1; k < errors.size(); ++k) {
        if (!std::isnan(errors[k]) && !std::isnan(errors[k - 1])) {
          intervals.push_back(std::fabs(errors[k] - errors[k - 1]));
        }
      }
    }
    const double median = Quantile(intervals, 0.5);
    const double p95 = Quantile(intervals, 0.95);
    std::printf("[ figures  ] chain %d Hz: interval error median %.1f us, p95 %.1f us\n", rate,
                median * 1e6, p95 * 1e6);
    EXPECT_LT(p95, rate == 16000 ? 200e-6 : kIntervalP95S) << rate;
    if (rate == 48000) {
      EXPECT_LT(median, kIntervalMedianS);
    }
  }
}

// A ping-pong ball on a wooden table: TableTopModes plus the ball's shell ringing near 3.2 kHz
// for 3-5 ms, a 300 us contact, air drag, a linear-phase chain, a room with two early echoes whose
// direct sound stands direct_to_reverberant_db over its tail, and noise 40 dB under the first
// impact. Loudness, height and restitution are the caller's.
// The table's room, recorded through a linear-phase chain: two early echoes (1.5 ms and 6 ms)
// and a diffuse tail, and noise at snr_db against the reference impact.
void RecordInTheTablesRoom(SynthesisOptions& options, double rt60_s,
                           double direct_to_reverberant_db, double snr_db, SnrReference reference) {
  options.chain = RecordingChain{};
  ReverbOptions reverb;
  reverb.rt60_s = rt60_s;
  reverb.direct_to_reverberant_db = direct_to_reverberant_db;
  reverb.echoes = {{0.0015, -14.0}, {0.006, -10.0}};
  options.reverb = reverb;
  NoiseOptions noise;
  noise.snr_db = snr_db;
  noise.reference = reference;
  options.noise = noise;
}

SynthesisOptions PingPongOnATable(std::uint64_t seed, double direct_to_reverberant_db) {
  SynthesisOptions options;
  options.seed = seed;
  options.modes = TableTopModes();
  for (double f : {3100.0, 3240.0, 3390.0}) options.modes.push_back({f, 0.004, 0.6});
  options.contact_duration_s = 300e-6;
  options.drop.terminal_speed_mps = 9.0;
  options.click_gain = 0.3;
  RecordInTheTablesRoom(options, 0.35, direct_to_reverberant_db, 40, SnrReference::kFirstImpact);
  return options;
}

// A ping-pong ball on a wooden table (TableTopModes plus the ball's shell ringing near 3.2 kHz for
// 3-5 ms), through a linear-phase chain, with air drag and noise 40 dB under the first impact: its
// late bounces are weak and land in the table's low ringing. There their first lobe sinks under
// the tail, the change point and the edge fit find the next lobe, and the onset is a lobe late
// (+110 to +170 us); stated with the shape terms alone (35-58 us) those onsets were 3 sigmas off
// (here 5 of 94 onsets, 89 of 94 within 2 sigmas; 85 % over the 8 seeds of
// bench/detector_accuracy_bench "ping-pong on table 40 dB re first"). An earlier lobe that came
// within half the reference level now widens the onset by half the distance to its edge
// (onset_picker.cc, kRivalLobeFraction): 1 and 93 of 94 here, 93 % in the bench.
TEST(DetectorGroundTruth, WeakBouncesOfAPingPongBallOnATableStateTheLobeTheyMayHaveSkipped) {
  int found = 0, covered = 0, late_uncovered = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    SynthesisOptions options = PingPongOnATable(seed, 3);
    options.peak_amplitude = 0.3 + 0.1 * static_cast<double>(seed);
    options.drop.drop_height_m = 0.25 + 0.05 * static_cast<double>(seed);
    options.drop.restitution.constant = 0.86 + 0.015 * static_cast<double>(seed);
    options.drop.min_flight_s = 0.02;
    const auto synthesized = SynthesizeBounces(options);
    const auto detection = Detect(synthesized.channels[0]);
    const auto score = Compare(detection.impacts, synthesized.BallImpactOnsetsS());
    Print("ping-pong on a table, seed " + std::to_string(seed), score);
    found += score.found;
    covered += score.within_two_sigma;
    // The lobe jump itself: an onset more than 80 us late (more than half the shell mode's period
    // of 310 us away from the first lobe's crossing, so on another lobe) outside 2 stated sigmas.
    for (const auto& impact : detection.impacts) {
      for (double t : synthesized.BallImpactOnsetsS()) {
        const double late = impact.onset_s - t - score.offset_s;
        if (std::fabs(impact.onset_s - t) < kMatchS && late > 80e-6 &&
            late > 2 * impact.onset_uncertainty_s) {
          ++late_uncovered;
        }
      }
    }
  }
  std::printf(
      "[ figures  ] ping-pong on a table: %d of %d onsets within 2 sigma, %d a lobe late "
      "outside them\n",
      covered, found, late_uncovered);
  // Honest Gaussian errors put 95.4 % within 2 sigmas.
  EXPECT_GE(covered, 0.95 * found);
  // The mechanism itself (5 before): one or two may remain where the skipped lobe stayed under
  // half the level, which no rule on the samples can tell from the tail.
  EXPECT_LE(late_uncovered, 2);
}

// The quiet end of a ping-pong ball's drop on a table in a drier room (direct sound 10 dB over
// the reverberation, 40 dB re the first impact): its bounces come every 25-35 ms, each clearly
// audible (rendered alone, its first 3 ms stand 7-12 dB over the 3.5 ms before it in the 1-4 kHz
// band, where the ball's shell rings: the independent suite's "required"), but none rises by the
// full threshold over the bounce before it. Their rises of half the threshold stood out of the
// noise under the ringing, not out of the bands' own floors, which the bounces' ringing had
// become: they were not kept as tentative impacts, and the sequence ended at the first of them.
TEST(DetectorGroundTruth, AQuietPingPongBallsLastAudibleBouncesStayInItsSequence) {
  int bounces = 0, in_sequence = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    SynthesisOptions options = PingPongOnATable(seed, 10);
    // Loudness and restitution vary with the seed as in bench/detector_accuracy_bench.
    const double w = std::fmod(0.7548776662 * static_cast<double>(seed), 1.0);
    options.peak_amplitude = 0.2 + 0.5 * std::fmod(0.5698402910 * static_cast<double>(seed), 1.0);
    options.drop.drop_height_m = 0.3;
    options.drop.restitution.constant = 0.88 + 0.04 * w;
    options.drop.min_flight_s = 0.012;
    const auto synthesized = SynthesizeBounces(options);
    auto detection = DetectImpacts(synthesized.channels[0]);
    const auto grouping = GroupBounces(detection);
    ASSERT_FALSE(grouping.sequences.empty()) << seed;
    const auto truth = synthesized.BallImpactOnsetsS();
    for (std::size_t k = 1; k < truth.size(); ++k) {
      if (truth[k] - truth[k - 1] < 0.025) continue;
      ++bounces;
      for (int i : grouping.sequences[0].impact_indices) {
        if (std::fabs(detection.impacts[static_cast<std::size_t>(i)].onset_s - truth[k]) <
            kMatchS) {
          ++in_sequence;
          break;
        }
      }
    }
  }
  std::printf(
      "[ figures  ] quiet ping-pong end: %d of %d bounces after flights >= 25 ms in the "
      "sequence\n",
      in_sequence, bounces);
  // 92 of 102 (90 %) before the tentative rises gated on the ringing's noise were kept, 97 now.
  // Of the 5 left, 2 are rises timed 1.7-2.1 ms late that no window takes, and the bounces after
  // them; 93 % leaves two bounces' margin for a change in timing.
  EXPECT_GE(in_sequence, 0.93 * bounces);
}

// A soft rubber ball (0.8 ms contact at 2 m/s, longer as it slows) on a wooden table, through a
// linear-phase chain, in a room (direct sound 4 dB over its tail), noise 30 dB under the weakest
// impact: bench/detector_accuracy_bench "rubber on table". Its later impacts land in the table's
// low ringing.
SynthesisOptions SoftBallOnATable(std::uint64_t seed) {
  const double s = static_cast<double>(seed);
  SynthesisOptions options;
  options.seed = seed;
  options.modes = TableTopModes();
  options.contact_duration_s = 800e-6;
  options.amplitude_speed_exponent = 1.5;
  options.peak_amplitude = 0.2 + 0.5 * std::fmod(0.5698402910 * s, 1.0);
  options.drop.drop_height_m = 0.5;
  options.drop.restitution.constant = 0.74 + 0.06 * std::fmod(0.7548776662 * s, 1.0);
  options.drop.min_flight_s = 0.03;
  options.click_gain = 0.15;
  RecordInTheTablesRoom(options, 0.3, 4, 30, SnrReference::kWeakestImpact);
  return options;
}

// The soft ball on a table: the table's low ringing swings in band 0 as loud as an impact's first
// millisecond, while the impact stands out at once in the 2 kHz band. A candidate opened just
// before such an impact (on the tail's own swing in that band) was closed a peak search after band
// 0's last peak, as the impact began; the impact's rest opened the next candidate, whose onset
// cannot be picked before the previous candidate's peak, and the merger kept that later, louder
// part: the onset 1.2 ms late at a stated 53 us (seed 6's 8th impact; bench/detector_accuracy_bench
// "rubber on table"). Now a candidate that rose by the full threshold and closed while that band
// was at its loudest so far, with its onset just before its window's end, does not bound the next
// candidate's pick window (Candidate::closed_rising, onset_locator.cc).
TEST(DetectorGroundTruth, ASoftBallsImpactRisingInASubBandIsNotSplitFromItsFirstMillisecond) {
  int band_detected = 0, late_unstated = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const SynthesisOptions options = SoftBallOnATable(seed);
    const auto synthesized = SynthesizeBounces(options);
    const auto detection = Detect(synthesized.channels[0]);
    const auto truth = synthesized.BallImpactOnsetsS();
    const auto score = Compare(detection.impacts, truth);
    for (const auto& impact : detection.impacts) {
      if (impact.residual_only) continue;
      // Within 3 ms of its bounce (the shortest flight is 30 ms): a split impact is matched too.
      double nearest = 1e9;
      for (double t : truth) {
        if (std::fabs(impact.onset_s - t) < std::fabs(nearest)) nearest = impact.onset_s - t;
      }
      if (std::fabs(nearest) > 3e-3) continue;
      ++band_detected;
      const double late = nearest - score.offset_s;
      if (late > 500e-6 && late > 3 * impact.onset_uncertainty_s) {
        ++late_unstated;
        std::printf("[ figures  ] seed %d: impact at %.4f s %+.0f us at a stated %.0f us\n",
                    static_cast<int>(seed), impact.onset_s, late * 1e6,
                    impact.onset_uncertainty_s * 1e6);
      }
    }
  }
  std::printf(
      "[ figures  ] soft ball on a table: %d band-detected impacts, %d more than 0.5 ms late "
      "beyond 3 stated sigmas\n",
      band_detected, late_unstated);
  // 1 before (seed 6: +1215 us at 53 us; now +132 us at 50 us). 0.5 ms is under the shortest
  // contact here and over every other band-detected onset's error (at most 470 us, stated
  // 307 us); 3 sigmas, because a late onset that states its lateness is honest.
  EXPECT_EQ(late_unstated, 0);
}

// The soft ball on a table at 48 and 16 kHz (below 20 kHz retimed from the whole response, as
// DetectImpactsInFile does). Where an onset's change point did not stand out of its search's start
// (AIC excess < 4), the whole search looked alike and the onset sits near its start, while the
// impact may have begun anywhere up to the window's peak: seed 6's 9th impact at 48 kHz was
// +306 us at a stated 50 us (a band-detected impact), and at 16 kHz seed 3's 10th -3.45 ms at a
// stated 1.3 ms (one residual hop, 2.6 sigmas). Half the search is now stated (594 us, 2.6 ms).
TEST(DetectorGroundTruth, AnOnsetWhoseChangePointDidNotStandOutStatesItsSearch) {
  int near = 0, unstated = 0;
  for (int rate : {48000, 16000}) {
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      SynthesisOptions options = SoftBallOnATable(seed);
      options.sample_rate_hz = rate;
      const auto synthesized = SynthesizeBounces(options);
      auto detection = DetectImpacts(synthesized.channels[0]);
      if (rate < 20000) RetimeFromResponses(detection, synthesized.channels[0].samples);
      GroupBounces(detection);
      const auto truth = synthesized.BallImpactOnsetsS();
      const auto score = Compare(detection.impacts, truth);
      for (const auto& impact : detection.impacts) {
        double nearest = 1e9;
        for (double t : truth) {
          if (std::fabs(impact.onset_s - t) < std::fabs(nearest)) nearest = impact.onset_s - t;
        }
        // Within 5 ms of its bounce (the shortest flight is 30 ms): an onset a search off too.
        if (std::fabs(nearest) > 5e-3) continue;
        ++near;
        const double error = std::fabs(nearest - score.offset_s);
        if (error > 250e-6 && error > 3 * impact.onset_uncertainty_s) {
          ++unstated;
          std::printf(
              "[ figures  ] %d Hz seed %d: impact at %.4f s %.0f us off at a stated %.0f us\n",
              rate, static_cast<int>(seed), impact.onset_s, error * 1e6,
              impact.onset_uncertainty_s * 1e6);
        }
      }
    }
  }
  std::printf(
      "[ figures  ] soft ball on a table, 48 and 16 kHz: %d impacts within 5 ms of a bounce, %d "
      "more than 250 us and 3 stated sigmas off\n",
      near, unstated);
  // 2 before the pick window change and this one (seed 6 at 48 kHz: +1216 us at 53 us, +306 us at
  // 50 us), 1 after the first. 250 us: over every other error here but those, under a soft
  // contact's duration; 3 sigmas, because an error its onset states is honest.
  EXPECT_EQ(unstated, 0);
}

}  // namespace
}  // namespace bouncecal::audio
