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

// The constant between an impact's response and its onset is the impacts' weighted median, and in
// a lossy file each detector onset weighs by its first lobe's error too: the template's own onset
// is as unreliable as any other there. Weighed by its detector sigma alone (tens of us), the
// loudest impact's onset, a pre-echo's start 2 ms early, set the constant for every aligned
// impact, which then disagreed with the ones left on their detector onsets (silent_wrong_sweep.py
// seed 9 #27's drop as MP3 64k once its codec noise no longer made up impacts: the first bounce
// the template, eta-bar 0.3616 +- 0.0069 against 0.3455).
TEST(ResponseTiming, InALossyFileTheTemplatesOwnOnsetDoesNotSetTheOthers) {
  constexpr double kCodecSigmaS = 967e-6;  // AAC 128k's table value (codec_timing.h)
  for (int seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    const auto drop = SteelDrop(seed, 48000);
    const auto truth = drop.BallImpactOnsetsS();
    auto detection = DetectImpacts(drop.channels[0]);
    const auto matched = Match(detection, truth);
    std::optional<std::size_t> loudest;
    for (std::size_t k = 0; k < matched.size(); ++k) {
      if (matched[k] && (!loudest || detection.impacts[*matched[k]].peak_dbfs >
                                         detection.impacts[*matched[*loudest]].peak_dbfs)) {
        loudest = k;
      }
    }
    ASSERT_TRUE(loudest.has_value());
    // The others state a few hundred us, as the detector does in a lossy file where a later attack
    // follows the onset (half their distance, ResponseTimingOptions::pre_echo); the loudest keeps
    // its clean first lobe's tens of us though its onset jumped 2 ms early.
    std::vector<double> before;
    for (std::size_t k = 0; k < matched.size(); ++k) {
      if (!matched[k] || k == *loudest) continue;
      Impact& impact = detection.impacts[*matched[k]];
      before.push_back(impact.onset_s - truth[k]);
      impact.onset_uncertainty_s = 300e-6;
    }
    detection.impacts[*matched[*loudest]].onset_s -= 2e-3;
    RetimeFromResponses(detection, drop.channels[0].samples, kCodecSigmaS);
    const auto after = Match(detection, truth);
    std::vector<double> errors;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      if (after[k]) errors.push_back(detection.impacts[*after[k]].onset_s - truth[k]);
    }
    // The others' onsets set where the aligned ones lie (50 us: two samples, the scatter of the
    // detector's onsets on this plate), and the jumped one comes back to them (100 us: its
    // alignment's own sigma, tens of us, beside that scatter; it was 2 ms off).
    EXPECT_NEAR(Median(errors), Median(before), 50e-6);
    ASSERT_TRUE(after[*loudest].has_value());
    EXPECT_NEAR(detection.impacts[*after[*loudest]].onset_s - truth[*loudest], Median(before),
                100e-6);
  }
}

// On a clean WAV the detector's onsets are already right to a sample: the stage agrees with them,
// so it only combines (never replaces) and no onset moves by more than its stated uncertainty.
// Nor does a sigma grow, but by the loudness law's share of the centroid shift
// (response_timing.cc): a sixth of a contact's lengthening, which for this 70 us contact, the
// last bounce 10 times slower than the first (60 % longer), is 7 us; 10 us in quadrature.
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
      EXPECT_LE(detection.impacts[i].onset_uncertainty_s,
                std::hypot(before.impacts[i].onset_uncertainty_s, 10e-6));
    }
  }
}

// The sounds the merger set aside name the impact they lost to by its onset, and the bounce
// sequence offers them as that impact's other sound only while the names agree
// (merged_alternatives.h): a retimed impact takes them along, an impact left where it was keeps
// them, and a sound that lost to no impact (a name matching none) is left alone.
TEST(ResponseTiming, SoundsMergedIntoAnImpactFollowItsRetimedOnset) {
  const auto drop = SteelDrop(1, 48000);
  auto detection = DetectImpacts(drop.channels[0]);
  ASSERT_GE(detection.impacts.size(), 6u);
  // One onset jumped 2 ms early, as a codec's pre-echo makes it: the stage replaces it.
  detection.impacts[3].onset_s -= 2e-3;
  detection.merged.clear();
  for (const Impact& impact : detection.impacts) {
    MergedEvent click;
    click.time_s = impact.onset_s - 5e-3;
    click.winner_s = impact.onset_s;
    detection.merged.push_back(click);
  }
  MergedEvent orphan;
  orphan.time_s = detection.impacts[2].onset_s + 4e-3;
  orphan.winner_s = detection.impacts[2].onset_s + 1e-3;  // no impact's onset
  detection.merged.push_back(orphan);
  const auto before = detection;
  RetimeFromResponses(detection, drop.channels[0].samples);
  ASSERT_EQ(detection.impacts.size(), before.impacts.size());
  ASSERT_NE(detection.impacts[3].onset_s, before.impacts[3].onset_s) << "nothing was retimed";
  for (std::size_t i = 0; i < detection.impacts.size(); ++i) {
    EXPECT_EQ(detection.merged[i].winner_s, detection.impacts[i].onset_s) << "impact " << i;
    EXPECT_EQ(detection.merged[i].time_s, before.merged[i].time_s);
  }
  EXPECT_EQ(detection.merged.back().winner_s, orphan.winner_s);
}

// A 20 ms white noise burst of standard deviation `sd` half a second before the end of a 48 kHz
// recording (after the last bounce); returns its onset (s).
double AddNoiseBurstAfterTheDrop(std::vector<float>& samples, float sd) {
  std::mt19937 random(3);
  std::normal_distribution<float> noise(0.0f, sd);
  const std::size_t burst = samples.size() - 24000;
  for (std::size_t i = burst; i < burst + 960; ++i) samples[i] += noise(random);
  return static_cast<double>(burst) / 48000;
}

// The drop's true onsets as detected impacts (+-20 us, -10 dBFS) and the burst at `burst_dbfs`.
DetectionResult TrueImpactsAndTheBurst(const SynthesizedRecording& drop, double burst_s,
                                       double burst_dbfs) {
  DetectionResult detection;
  detection.sample_rate_hz = 48000;
  for (double t : drop.BallImpactOnsetsS()) {
    detection.impacts.push_back({.onset_s = t, .onset_uncertainty_s = 20e-6, .peak_dbfs = -10});
  }
  detection.impacts.push_back(
      {.onset_s = burst_s, .onset_uncertainty_s = 20e-6, .peak_dbfs = burst_dbfs});
  return detection;
}

// A sound unlike the recording's impacts (white noise burst) correlates with no lag clearly
// better than with the others: it is left as the detector timed it.
TEST(ResponseTiming, ASoundUnlikeTheImpactsIsNotAligned) {
  const auto drop = SteelDrop(2, 48000);
  auto samples = drop.channels[0].samples;
  const double burst_s = AddNoiseBurstAfterTheDrop(samples, 0.1f);
  auto detection = TrueImpactsAndTheBurst(drop, burst_s, -20);
  const auto summary = RetimeFromResponses(detection, samples);
  EXPECT_EQ(summary.aligned, static_cast<int>(detection.impacts.size()) - 1);
  EXPECT_EQ(detection.impacts.back().onset_s, burst_s);
}

// The loudest sound of a recording need not be an impact of the ball (the suite's
// pingpong_table as AAC 128k: a reflection the codec made rise like an impact, 1.5 dB louder
// than the first bounce). A template nothing else resembles would leave every bounce unaligned;
// the template is the loudest sound that at least half the other loud ones align with.
TEST(ResponseTiming, ALouderSoundUnlikeTheImpactsIsNotTheTemplate) {
  const auto drop = SteelDrop(2, 48000);
  auto samples = drop.channels[0].samples;
  const double burst_s = AddNoiseBurstAfterTheDrop(samples, 0.3f);
  auto detection = TrueImpactsAndTheBurst(drop, burst_s, -3);
  const auto truth = drop.BallImpactOnsetsS();
  const auto summary = RetimeFromResponses(detection, samples);
  ASSERT_GE(summary.template_onset_sample, 0);
  const double template_s = static_cast<double>(summary.template_onset_sample) / 48000;
  EXPECT_LT(std::fabs(template_s - truth.front()), 1e-4)
      << "template at " << template_s << " s, first bounce at " << truth.front() << " s";
  EXPECT_EQ(summary.aligned, static_cast<int>(truth.size()));
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
  const double burst_s = AddNoiseBurstAfterTheDrop(samples, 0.1f);
  auto detection = DetectImpacts(drop.channels[0]);
  // Pre-echo: every third found impact jumped 1.5-2.5 ms early.
  const auto matched = Match(detection, truth);
  for (std::size_t k = 1; k < matched.size(); k += 3) {
    if (matched[k])
      detection.impacts[*matched[k]].onset_s -= 1.5e-3 + 1e-3 * std::fmod(0.618 * k, 1.0);
  }
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

// A ball that lands on a different spot of a dense plate at every bounce (a 20 x 13 cm, 1.2 mm
// plate like CounterTopModes', with a higher loss factor so that its ringing has died down before
// the next bounce), each spot exciting the same modes with its own gains and signs: the
// impacts' waveforms are a different mix of the modes, as a real ball's are (ping-pong, tennis
// ball, basketball: rho 0.2-0.5 between impacts, docs/codecs.md), while the energy in each
// octave band rises and decays alike.
struct SpotDrop {
  std::vector<float> samples;
  std::vector<double> truth;
};
SpotDrop DropOnRandomSpots(int seed) {
  SynthesisOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  options.sample_rate_hz = 48000;
  options.peak_amplitude = 0.4;
  options.drop.drop_height_m = 0.25;
  options.drop.restitution.constant = 0.7;
  options.drop.min_flight_s = 0.03;
  options.contact_duration_s = 50e-6;
  const auto planned = PlanBallImpacts(options);
  options.duration_s = planned.back().onset_s + 0.2;
  SpotDrop drop;
  drop.samples.assign(static_cast<std::size_t>(options.duration_s * options.sample_rate_hz), 0.0f);
  std::mt19937 random(static_cast<std::uint32_t>(seed));
  std::uniform_real_distribution<double> spot(0.1, 0.9);
  for (const auto& impact : planned) {
    RectangularPlate plate;
    plate.length_m = 0.20;
    plate.width_m = 0.13;
    plate.thickness_m = 1.2e-3;
    plate.loss_factor = 3e-2;
    plate.max_frequency_hz = 18000;
    plate.impact_x_fraction = spot(random);
    plate.impact_y_fraction = spot(random);
    SynthesisOptions one = options;
    one.impacts = {ImpactSpec{
        .onset_s = impact.onset_s, .impact_speed_mps = impact.impact_speed_mps, .drop_index = 0}};
    one.modes = RectangularPlateModes(plate);
    const auto rendered = SynthesizeBounces(one);
    const auto& samples = rendered.channels[0].samples;
    for (std::size_t i = 0; i < drop.samples.size() && i < samples.size(); ++i) {
      drop.samples[i] += samples[i];
    }
    drop.truth.push_back(impact.onset_s);
  }
  std::normal_distribution<float> noise(0.0f, 1e-4f);  // -80 dBFS
  for (float& s : drop.samples) s += noise(random);
  return drop;
}

// Issue 30: a transform codec's pre-echo moves some of a real ball's onsets early by
// milliseconds, and those impacts' waveforms do not align with the template's. Their band
// envelopes do (envelope_alignment.h): the jumped onsets come back to the others' timing, and
// every onset's stated sigma covers its error with much less than the codec table's sigma.
// Without the envelopes (the option off) the jumped onsets stay milliseconds off.
TEST(ResponseTiming, ImpactsWhoseWaveformsDifferAreTimedFromTheirEnvelopes) {
  constexpr double kCodecSigma = 967e-6;  // AAC 128k's table sigma
  int jumped = 0;
  int restored = 0;
  int restored_without = 0;
  int envelope_timed = 0;
  int others = 0;  // impacts not jumped
  for (int seed = 1; seed <= 3; ++seed) {
    auto drop = DropOnRandomSpots(seed);
    Recording recording;
    recording.sample_rate_hz = 48000;
    recording.samples = drop.samples;
    auto detection = DetectImpacts(recording);
    const auto matched = Match(detection, drop.truth);
    // Pre-echo: quantisation noise spread over the 1.5-2.5 ms before every third found impact
    // (not the first), 30 dB under the impact's peak, and the detector's onset at its start.
    std::vector<std::size_t> moved;
    std::normal_distribution<float> noise(0.0f, 0.01f);
    std::mt19937 random(static_cast<std::uint32_t>(seed) + 100);
    for (std::size_t k = 1; k < matched.size(); k += 3) {
      if (!matched[k]) continue;
      const double jump = 1.5e-3 + 1e-3 * std::fmod(0.618 * static_cast<double>(k), 1.0);
      const auto from = static_cast<std::size_t>((drop.truth[k] - jump) * 48000);
      const auto to = static_cast<std::size_t>(drop.truth[k] * 48000);
      for (std::size_t i = from; i < to; ++i) drop.samples[i] += noise(random);
      detection.impacts[*matched[k]].onset_s = drop.truth[k] - jump;
      moved.push_back(k);
    }
    ASSERT_FALSE(moved.empty());
    jumped += static_cast<int>(moved.size());
    others += static_cast<int>(drop.truth.size() - moved.size());
    ResponseTimingOptions options;
    for (bool envelopes : {false, true}) {
      options.envelope_alignment = envelopes;
      auto retimed = detection;
      const auto summary = RetimeFromResponses(retimed, drop.samples, kCodecSigma, options);
      // The waveforms of most impacts do not align.
      EXPECT_LT(summary.aligned, static_cast<int>(drop.truth.size()) / 2) << "seed " << seed;
      const auto after = Match(retimed, drop.truth);
      std::vector<double> errors;
      for (std::size_t k = 0; k < drop.truth.size(); ++k) {
        if (after[k]) errors.push_back(retimed.impacts[*after[k]].onset_s - drop.truth[k]);
      }
      const double offset = Median(errors);
      for (std::size_t k = 0; k < drop.truth.size(); ++k) {
        if (!after[k]) continue;
        const Impact& impact = retimed.impacts[*after[k]];
        const double error = impact.onset_s - drop.truth[k] - offset;
        const bool was_moved = std::find(moved.begin(), moved.end(), k) != moved.end();
        // 150 us: the envelopes are decimated to 12 kHz, so their sigma is at least one step (83
        // us); a lossy copy of a real ping-pong recording puts them within 60-100 us of its
        // WAV's first lobes (ub-mth337 pingpong.wav, AAC and Opus).
        const bool back = was_moved && std::fabs(error) <= 150e-6;
        if (!envelopes) {
          restored_without += back ? 1 : 0;
          continue;
        }
        restored += back ? 1 : 0;
        // Timed from the envelopes: a confirmed onset is stated with their precision, not the
        // codec table's; a replaced one with half the 1.5-2.5 ms jump as well (either could have
        // slipped). The others (an ambiguous envelope correlation: another lag within 0.15 of
        // the peak) keep the detector's onset and the table's sigma, as before.
        const bool confirmed = !was_moved && impact.onset_uncertainty_s < 0.5 * kCodecSigma;
        envelope_timed += confirmed ? 1 : 0;
        // Every error of an onset the envelopes timed within 1.96 stated sigmas, as the
        // waveform's (codec bench, 100 %).
        if (confirmed || back) {
          EXPECT_LE(std::fabs(error), 1.96 * impact.onset_uncertainty_s)
              << "seed " << seed << " impact " << k << " stated "
              << impact.onset_uncertainty_s * 1e6 << " us";
        }
      }
    }
  }
  // Half the impacts at least are timed from their envelopes (10 of 15 others and 5 of 9 jumped
  // ones when written; the rest ambiguous); without the envelopes none of the jumped ones comes
  // back.
  EXPECT_GE(2 * envelope_timed, others);
  EXPECT_GE(2 * restored, jumped);
  EXPECT_EQ(restored_without, 0);
}

}  // namespace
}  // namespace bouncecal::audio
