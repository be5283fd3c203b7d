#include "bouncecal/audio/response_timing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {
namespace {

// A steel ball on a table-damped steel plate (modes ring a few ms to tens of ms), 30 dB SNR
// referred to the weakest impact, as in bench/codec_timing_bench.
SynthesizedRecording SteelDrop(int seed, int rate_hz) {
  SynthesisOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  options.sample_rate_hz = rate_hz;
  options.peak_amplitude = 0.4;
  options.drop.drop_height_m = 0.25;
  options.drop.restitution.constant = 0.7;
  options.drop.min_flight_s = 0.03;
  NoiseOptions noise;
  noise.snr_db = 30;
  noise.reference = SnrReference::kWeakestImpact;
  options.noise = noise;
  for (auto& mode : options.modes) mode.decay_s *= 0.1;
  return SynthesizeBounces(options);
}

// The detected impact nearest each true onset (within 5 ms), as an index.
std::vector<std::optional<std::size_t>> Match(const DetectionResult& detection,
                                              const std::vector<double>& truth) {
  std::vector<std::optional<std::size_t>> matched;
  for (double t : truth) {
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < detection.impacts.size(); ++i) {
      const double error = std::fabs(detection.impacts[i].onset_s - t);
      if (error < 5e-3 && (!best || error < std::fabs(detection.impacts[*best].onset_s - t))) {
        best = i;
      }
    }
    matched.push_back(best);
  }
  return matched;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// What a codec's pre-echo does to the detector: a few onsets jump early by milliseconds with the
// uncertainty of a clean first lobe. Aligning each impact's response to the recording's template
// brings them back to the others' timing, and the stated uncertainty covers what is left.
TEST(ResponseTiming, OnsetsThatJumpedEarlyAreRetimedFromTheResponse) {
  int jumped = 0;
  int restored = 0;
  for (int seed = 1; seed <= 4; ++seed) {
    const auto drop = SteelDrop(seed, 48000);
    const auto truth = drop.BallImpactOnsetsS();
    auto detection = DetectImpacts(drop.channels[0]);
    const auto matched = Match(detection, truth);
    // Jump every third found impact (not the loudest, the first) 1.5-2.5 ms early.
    std::vector<std::size_t> moved;
    for (std::size_t k = 1; k < matched.size(); k += 3) {
      if (!matched[k]) continue;
      detection.impacts[*matched[k]].onset_s -= 1.5e-3 + 1e-3 * std::fmod(0.618 * k, 1.0);
      moved.push_back(k);
    }
    ASSERT_FALSE(moved.empty());
    jumped += static_cast<int>(moved.size());
    const auto summary = RetimeFromResponses(detection, drop.channels[0].samples);
    EXPECT_GE(summary.replaced, static_cast<int>(moved.size()));
    const auto after = Match(detection, truth);
    std::vector<double> errors;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      if (after[k]) errors.push_back(detection.impacts[*after[k]].onset_s - truth[k]);
    }
    const double offset = Median(errors);
    for (std::size_t k : moved) {
      ASSERT_TRUE(after[k].has_value());
      const Impact& impact = detection.impacts[*after[k]];
      const double error = impact.onset_s - truth[k] - offset;
      // 50 us: two samples, the WAV detector's own interval p95 on this plate (detector.md).
      if (std::fabs(error) <= 50e-6 && std::fabs(error) <= 3 * impact.onset_uncertainty_s) {
        ++restored;
      } else {
        ADD_FAILURE() << "seed " << seed << " impact " << k << ": " << error * 1e6 << " us, stated "
                      << impact.onset_uncertainty_s * 1e6 << " us";
      }
    }
  }
  // Every jumped onset is restored; none may stay milliseconds off.
  EXPECT_EQ(restored, jumped);
}

// On a clean WAV the detector's onsets are already right to a sample: the stage agrees with them,
// so it only combines (never replaces) and no onset moves by more than its stated uncertainty.
TEST(ResponseTiming, CleanOnsetsAreCombinedNotReplaced) {
  for (int seed = 1; seed <= 3; ++seed) {
    const auto drop = SteelDrop(seed, 48000);
    auto detection = DetectImpacts(drop.channels[0]);
    const auto before = detection;
    const auto summary = RetimeFromResponses(detection, drop.channels[0].samples);
    EXPECT_GT(summary.aligned, 3);
    EXPECT_EQ(summary.replaced, 0);
    ASSERT_EQ(detection.impacts.size(), before.impacts.size());
    for (std::size_t i = 0; i < before.impacts.size(); ++i) {
      EXPECT_LE(std::fabs(detection.impacts[i].onset_s - before.impacts[i].onset_s),
                3 * before.impacts[i].onset_uncertainty_s);
      EXPECT_LE(detection.impacts[i].onset_uncertainty_s, before.impacts[i].onset_uncertainty_s);
    }
  }
}

// A sound unlike the recording's impacts (white noise burst) correlates with no lag clearly
// better than with the others: it is left as the detector timed it.
TEST(ResponseTiming, ASoundUnlikeTheImpactsIsNotAligned) {
  const auto drop = SteelDrop(2, 48000);
  auto samples = drop.channels[0].samples;
  std::mt19937 random(3);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  const std::size_t burst = samples.size() - 24000;  // after the last bounce
  for (std::size_t i = burst; i < burst + 960; ++i) samples[i] += noise(random);
  DetectionResult detection;
  detection.sample_rate_hz = 48000;
  for (double t : drop.BallImpactOnsetsS()) detection.impacts.push_back({.onset_s = t});
  for (auto& impact : detection.impacts) {
    impact.onset_uncertainty_s = 20e-6;
    impact.peak_dbfs = -10;
  }
  const double burst_s = static_cast<double>(burst) / 48000;
  detection.impacts.push_back({.onset_s = burst_s, .onset_uncertainty_s = 20e-6, .peak_dbfs = -20});
  const auto summary = RetimeFromResponses(detection, samples);
  EXPECT_EQ(summary.aligned, static_cast<int>(detection.impacts.size()) - 1);
  EXPECT_EQ(detection.impacts.back().onset_s, burst_s);
}

// With a codec's first-lobe error (AAC 128k's table sigma, 967 us) on every detector onset, an
// impact the alignment times is stated with the alignment's precision where the detector's onset
// agrees, with half their disagreement where it jumped, and its error is covered either way; a
// sound the alignment cannot time keeps the detector's onset with the codec's error.
TEST(ResponseTiming, AlignedImpactsAreStatedWithTheAlignmentsPrecisionOthersWithTheCodecs) {
  constexpr double kCodecSigma = 967e-6;
  const auto drop = SteelDrop(2, 48000);
  const auto truth = drop.BallImpactOnsetsS();
  auto samples = drop.channels[0].samples;
  std::mt19937 random(3);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  const std::size_t burst = samples.size() - 24000;  // after the last bounce
  for (std::size_t i = burst; i < burst + 960; ++i) samples[i] += noise(random);
  auto detection = DetectImpacts(drop.channels[0]);
  // Pre-echo: every third found impact jumped 1.5-2.5 ms early.
  const auto matched = Match(detection, truth);
  for (std::size_t k = 1; k < matched.size(); k += 3) {
    if (matched[k])
      detection.impacts[*matched[k]].onset_s -= 1.5e-3 + 1e-3 * std::fmod(0.618 * k, 1.0);
  }
  const double burst_s = static_cast<double>(burst) / 48000;
  detection.impacts.push_back({.onset_s = burst_s, .onset_uncertainty_s = 20e-6, .peak_dbfs = -20});
  const auto summary = RetimeFromResponses(detection, samples, kCodecSigma);
  EXPECT_EQ(summary.own_sigma, summary.aligned);
  EXPECT_GE(summary.aligned, static_cast<int>(truth.size()) - 2);
  const auto after = Match(detection, truth);
  std::vector<double> errors;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (after[k]) errors.push_back(detection.impacts[*after[k]].onset_s - truth[k]);
  }
  const double offset = Median(errors);
  int precise = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (!after[k]) continue;
    const Impact& impact = detection.impacts[*after[k]];
    // Every aligned impact's error lies within 1.96 of its stated sigma (the bench's coverage,
    // 100 % at 48 kHz).
    EXPECT_LE(std::fabs(impact.onset_s - truth[k] - offset), 1.96 * impact.onset_uncertainty_s)
        << "impact " << k << " stated " << impact.onset_uncertainty_s * 1e6 << " us";
    // Where the detector's onset agreed, the alignment's sigma is all that is stated: at least
    // half a sample (10 us), at most a few samples here. A jumped onset leaves half its 1.5-2.5
    // ms jump unexplained (either measurement could be the one that slipped), so it is stated
    // with at least that.
    const bool jumped = k % 3 == 1;
    if (jumped) {
      EXPECT_GE(impact.onset_uncertainty_s, 0.5 * 1.5e-3 * 0.9) << k;
    } else {
      EXPECT_LE(impact.onset_uncertainty_s, 100e-6) << k;
      ++precise;
    }
  }
  EXPECT_GE(precise, static_cast<int>(truth.size()) / 2);
  const auto noise_burst = std::find_if(detection.impacts.begin(), detection.impacts.end(),
                                        [&](const Impact& i) { return i.onset_s == burst_s; });
  ASSERT_NE(noise_burst, detection.impacts.end());
  EXPECT_DOUBLE_EQ(noise_burst->onset_uncertainty_s, std::hypot(20e-6, kCodecSigma));
}

TEST(ResponseTiming, RunsOnlyWhereTheFirstLobeIsUnreliable) {
  RecordingInfo info;
  info.sample_rate_hz = 48000;
  EXPECT_FALSE(FirstLobeUnreliable(info));
  info.lossy = true;
  info.codec = "aac";
  EXPECT_TRUE(FirstLobeUnreliable(info));
  info.codec = "pcm_mulaw";
  EXPECT_FALSE(FirstLobeUnreliable(info));
  info.sample_rate_hz = 8000;
  EXPECT_TRUE(FirstLobeUnreliable(info));
}

}  // namespace
}  // namespace bouncecal::audio
