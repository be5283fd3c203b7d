#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/audio/write_recording.h"
#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "synthetic_drop.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

fs::path WriteWav(const std::string& name, std::vector<float> samples, int rate = 48000,
                  audio::SampleEncoding encoding = audio::SampleEncoding::kPcm16) {
  audio::Recording recording;
  recording.sample_rate_hz = rate;
  recording.samples = std::move(samples);
  const auto path = ScratchPath(name);
  audio::WriteRecording(path, std::span<const audio::Recording>(&recording, 1),
                        {audio::AudioContainer::kWav, encoding});
  return path;
}

// The table-damped steel drop of synthetic_drop.h.
fs::path SyntheticDrop(const std::string& name, std::uint64_t seed, double height_m) {
  return WriteTableDampedDrop(ScratchPath(name), height_m, seed);
}

// The first sequence `analyze` finds in `wav` (its JSON report written to the scratch file
// `json_name`), or null where the command fails.
nlohmann::json FirstSequenceOf(const fs::path& wav, const std::string& json_name) {
  const auto json = ScratchPath(json_name);
  const auto analyzed =
      RunBouncecal("analyze '" + wav.string() + "' --json '" + json.string() + "'");
  EXPECT_EQ(analyzed.exit_status, 0) << analyzed.output;
  if (analyzed.exit_status != 0) return nullptr;
  return ReadJsonFile(json)["recordings"][0]["sequences"][0];
}

// Each of a sequence's first `count` onsets, less `offset_s`, lies within 3 of its stated sigmas
// of the true onset or within 0.5 ms (half a 1 ms contact, which a weak onset may miss by
// honestly): an onset that states its doubt is honest.
void ExpectOnsetsHonest(const nlohmann::json& sequence, const std::vector<double>& truth,
                        std::size_t count, double offset_s) {
  const auto onsets = sequence["onsets_s"].get<std::vector<double>>();
  const auto sigmas = sequence["onset_uncertainty_s"].get<std::vector<double>>();
  for (std::size_t k = 0; k < count; ++k) {
    const double error = onsets[k] - truth[k] - offset_s;
    EXPECT_FALSE(std::fabs(error) > 500e-6 && std::fabs(error) > 3 * sigmas[k])
        << "bounce " << k + 1 << ": " << error * 1e6 << " us at a stated " << sigmas[k] * 1e6
        << " us";
  }
}

// Intervals see the onsets less the recording's common offset: here that of the most precisely
// stated of the sequence's first `count` onsets, against the bounce at the same index.
double OffsetOfTheMostPreciselyStated(const nlohmann::json& sequence,
                                      const std::vector<double>& truth, std::size_t count) {
  const auto onsets = sequence["onsets_s"].get<std::vector<double>>();
  const auto sigmas = sequence["onset_uncertainty_s"].get<std::vector<double>>();
  std::size_t reference = 0;
  for (std::size_t k = 1; k < count; ++k) {
    if (sigmas[k] < sigmas[reference]) reference = k;
  }
  return onsets[reference] - truth[reference];
}

// A bad input gives exit status 2, one line that names the file, and no output file.
void ExpectInputError(const fs::path& input, const std::string& what) {
  const auto json = ScratchPath("should_not_exist.json");
  fs::remove(json);
  const auto result =
      RunBouncecal("analyze '" + input.string() + "' --json '" + json.string() + "'");
  EXPECT_EQ(result.exit_status, 2) << what << ": " << result.output;
  EXPECT_NE(result.output.find(input.string()), std::string::npos) << what << ": " << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(fs::exists(json)) << what;
}

TEST(AnalyzeCli, BadInputsAreOneLineErrorsWithExitStatus2) {
  ExpectInputError("/nonexistent/drop.wav", "missing");
  const auto empty = ScratchPath("empty.wav");
  std::ofstream(empty).close();
  ExpectInputError(empty, "empty");
  const auto text = ScratchPath("text.wav");
  std::ofstream(text) << "not a recording\n";
  ExpectInputError(text, "text renamed .wav");
  const auto whole = WriteWav("whole.wav", std::vector<float>(48000, 0.01f));
  std::ifstream in(whole, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto truncated = ScratchPath("truncated.wav");
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  ExpectInputError(truncated, "truncated");
  std::vector<float> with_nan(1000, 0.0f);
  with_nan[500] = std::numeric_limits<float>::quiet_NaN();
  ExpectInputError(WriteWav("nan.wav", with_nan, 48000, audio::SampleEncoding::kFloat), "NaN");
  ExpectInputError(WriteWav("zero.wav", {}), "0 samples");
  ExpectInputError(WriteWav("one.wav", {0.5f}), "1 sample");
}

TEST(AnalyzeCli, AGoodFileDoesNotSaveABadOneFromFailing) {
  const auto good = SyntheticDrop("good.wav", 3, 0.2);
  const auto json = ScratchPath("mixed.json");
  fs::remove(json);
  const auto result = RunBouncecal("analyze '" + good.string() + "' /nonexistent/b.wav --json '" +
                                   json.string() + "'");
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_FALSE(fs::exists(json));
}

TEST(AnalyzeCli, SilenceGivesEmptyListsANoteAndExitStatus0) {
  const auto silence = WriteWav("silence.wav", std::vector<float>(96000, 0.0f));
  const auto json = ScratchPath("silence.json");
  const auto result =
      RunBouncecal("analyze '" + silence.string() + "' --json '" + json.string() + "'");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("no impacts"), std::string::npos) << result.output;
  const auto out = ReadJsonFile(json)["recordings"][0];
  EXPECT_TRUE(out["impacts"].empty());
  EXPECT_TRUE(out["rejected_events"].empty());
  EXPECT_TRUE(out["sequences"].empty());
}

TEST(AnalyzeCli, JsonOfOneRecordingHasTheFormatAndTheDropHeightGivesTheFirstImpact) {
  const auto drop = SyntheticDrop("drop.wav", 5, 0.2);
  const auto json = ScratchPath("drop.json");
  const auto csv = ScratchPath("drop.csv");
  const auto result = RunBouncecal("analyze '" + drop.string() + "' --drop-height-m 0.2 --json '" +
                                   json.string() + "' --csv '" + csv.string() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto document = ReadJsonFile(json);
  EXPECT_EQ(document["format"], "bouncecal-analysis/1");
  ASSERT_EQ(document["recordings"].size(), 1u);
  EXPECT_EQ(document["summary"]["recordings"], 1);
  const auto& out = document["recordings"][0];
  // The deprecated pre-format shape, kept for one release: the one recording's fields also at
  // the top level, identical, so an old script reads the same onsets.
  for (const auto& [key, value] : out.items()) EXPECT_EQ(document[key], value) << key;
  EXPECT_TRUE(out["file"].is_string());
  EXPECT_EQ(out["sample_rate_hz"], 48000);
  EXPECT_EQ(out["channel"], 0);
  ASSERT_FALSE(out["impacts"].empty());
  for (const auto& impact : out["impacts"]) {
    EXPECT_TRUE(impact["onset_s"].is_number());
    EXPECT_TRUE(impact["onset_uncertainty_s"].is_number());
    EXPECT_TRUE(impact["peak_dbfs"].is_number());
    EXPECT_TRUE(impact["sequence"].is_number() || impact["sequence"].is_null());
  }
  EXPECT_TRUE(out["rejected_events"].is_array());
  ASSERT_GE(out["sequences"].size(), 1u);
  const auto& sequence = out["sequences"][0];
  for (const char* key :
       {"onsets_s", "intervals_s", "restitution", "energy_loss", "bounce_height_m"}) {
    EXPECT_TRUE(sequence[key].is_array()) << key;
  }
  // With the drop height every impact with an outgoing flight has an e: one more than intervals
  // minus one.
  EXPECT_EQ(sequence["restitution"].size(), sequence["intervals_s"].size());
  // The synthetic ball has e = 0.648 (eta = 0.58, the paper's value) at every speed; the first
  // three detected impacts give it back within 0.02 (onset errors of tens of us on flights of
  // 0.1-0.3 s move e by < 0.001; the margin covers a missed or extra impact changing N).
  ASSERT_TRUE(sequence["energy_loss_mean_first_n"].is_number());
  EXPECT_NEAR(sequence["energy_loss_mean_first_n"].get<double>(), 0.58, 0.02);
  std::ifstream csv_in(csv);
  std::string header;
  std::getline(csv_in, header);
  EXPECT_EQ(header.rfind("file,channel,sequence,k,onset_s", 0), 0u) << header;
}

TEST(AnalyzeCli, SeveralRecordingsGiveTheSameShapeWithOneEntryEachAndASummary) {
  const auto a = SyntheticDrop("a.wav", 11, 0.2);
  const auto b = SyntheticDrop("b.wav", 12, 0.25);
  const auto json = ScratchPath("two.json");
  const auto result = RunBouncecal("analyze '" + a.string() + "' '" + b.string() + "' --json '" +
                                   json.string() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto out = ReadJsonFile(json);
  ASSERT_TRUE(out.is_object());
  EXPECT_EQ(out["format"], "bouncecal-analysis/1");
  ASSERT_EQ(out["recordings"].size(), 2u);
  EXPECT_EQ(out["recordings"][0]["file"], a.string());
  EXPECT_EQ(out["recordings"][1]["file"], b.string());
  EXPECT_EQ(out["summary"]["recordings"], 2);
  EXPECT_TRUE(out["summary"]["energy_loss_mean"].is_number());
  EXPECT_FALSE(out.contains("impacts"));  // the top-level copy is for one recording only
}

// A drop of 6 bounces (e = 0.65 from 0.20 m) followed by knocks at irregular times, which no
// bounce sequence can hold: with more knocks than bounces analyze says the sequence may rest on
// a few of many sounds; with fewer it does not (the rule: more left out than in, and at least 4).
TEST(AnalyzeCli, MostImpactsOutsideEverySequenceAreAWarningFewAreNot) {
  const auto analyze_with_knocks = [](const std::vector<double>& knocks_s) {
    const auto csv = ScratchPath("impacts_" + std::to_string(knocks_s.size()) + ".csv");
    std::ofstream out(csv);
    double t = 0.5, v = std::sqrt(2 * 9.81 * 0.2);
    for (int k = 0; k < 6; ++k, v *= 0.65, t += 2 * v / 9.81) out << t << "," << v << "\n";
    for (std::size_t i = 0; i < knocks_s.size(); ++i)
      out << knocks_s[i] << "," << (i % 2 ? 1.5 : 1.0) << "\n";
    out.close();
    const auto wav = ScratchPath("knocks_" + std::to_string(knocks_s.size()) + ".wav");
    const auto synth = RunBouncecal("synth -o '" + wav.string() + "' --impact-times '" +
                                    csv.string() + "' --snr-db 40 --reverb-rt60-s 0.2");
    EXPECT_EQ(synth.exit_status, 0) << synth.output;
    return RunBouncecal("analyze '" + wav.string() + "'");
  };
  const auto many = analyze_with_knocks({2.3, 2.95, 3.42, 4.61, 5.07, 5.93, 6.58, 7.44});
  EXPECT_EQ(many.exit_status, 0) << many.output;
  EXPECT_NE(many.output.find("1 sequence(s)"), std::string::npos) << many.output;
  EXPECT_NE(many.output.find("8 of 14 impacts fit no bounce sequence"), std::string::npos)
      << many.output;
  const auto few = analyze_with_knocks({2.3, 3.42, 5.07, 6.58});
  EXPECT_EQ(few.exit_status, 0) << few.output;
  EXPECT_NE(few.output.find("1 sequence(s)"), std::string::npos) << few.output;
  EXPECT_EQ(few.output.find("fit no bounce sequence"), std::string::npos) << few.output;
}

// The codec line says which timing a lossless file's onsets have: timed from their whole
// response where the drop determined its contact durations (docs/detector.md), otherwise nothing
// is added (a drop of three impacts fixes no duration).
TEST(AnalyzeCli, ALosslessFileSaysWhenItsOnsetsWereTimedFromTheirResponse) {
  const auto drop = RunBouncecal("synth -o '" + ScratchPath("anvil.wav").string() +
                                 "' --drop-height-m 0.35 --restitution 0.8 --min-flight-s 0.03 "
                                 "--reverb-rt60-s 0.3 --snr-db 35 --seed 1");
  ASSERT_EQ(drop.exit_status, 0) << drop.output;
  const auto timed = RunBouncecal("analyze '" + ScratchPath("anvil.wav").string() + "'");
  EXPECT_EQ(timed.exit_status, 0) << timed.output;
  EXPECT_NE(timed.output.find("lossless; "), std::string::npos) << timed.output;
  EXPECT_NE(timed.output.find("onsets timed from their impact's whole response"), std::string::npos)
      << timed.output;
  const auto csv = ScratchPath("three.csv");
  std::ofstream(csv) << "0.5,2.0\n1.0,1.4\n1.35,1.0\n";
  const auto three = RunBouncecal("synth -o '" + ScratchPath("three.wav").string() +
                                  "' --impact-times '" + csv.string() + "' --snr-db 40");
  ASSERT_EQ(three.exit_status, 0) << three.output;
  const auto first_lobe = RunBouncecal("analyze '" + ScratchPath("three.wav").string() + "'");
  EXPECT_EQ(first_lobe.exit_status, 0) << first_lobe.output;
  EXPECT_EQ(first_lobe.output.find("timed from their impact's whole response"), std::string::npos)
      << first_lobe.output;
}

// Renders `bouncecal synth` with `options` to `wav` and returns its ball's impact times (the truth
// CSV's ball_impact rows); empty, with a test failure, where synth fails.
std::vector<double> SynthesizedBounceTimes(const fs::path& wav, const std::string& options) {
  const auto truth_csv = fs::path(wav).replace_extension(".csv");
  const auto synth = RunBouncecal("synth -o '" + wav.string() + "' --truth '" + truth_csv.string() +
                                  "' " + options);
  EXPECT_EQ(synth.exit_status, 0) << synth.output;
  std::vector<double> truth;
  std::ifstream in(truth_csv);
  for (std::string line; std::getline(in, line);) {
    if (line.find(",ball_impact,") != std::string::npos) truth.push_back(std::stod(line));
  }
  return truth;
}

// A faint precursor 5.5 ms before every bounce (-21 dB), an echo 2.8 ms after it (-8 dB) and a
// 1 ms contact on the plate at 44.1 kHz, written as 16-bit PCM whose first bounce clips (136
// samples), as the sweep's file does (bench/silent_wrong_sweep.py seed 11 #146). A precursor inside
// the previous bounce's ringing is found on the prediction innovation, whose window ends at the
// candidate's largest innovation sample: that sample was the 5th bounce's own first lobe, and as
// the floor of the next pick window it left the bounce's picker 0.15 ms before the bounce. The
// onset was picked 1.36 ms late at a stated 54 us, and eta-bar lay 17.7 combined sigmas from the
// exact onsets'. An onset found inside ringing now bounds the next pick only at itself (this one:
// 229 us early at a stated 104 us).
TEST(AnalyzeCli, APrecursorInRingingDoesNotCutTheNextBouncesPickWindow) {
  const auto wav = ScratchPath("precursor.wav");
  const auto truth = SynthesizedBounceTimes(
      wav,
      "--sample-rate-hz 44100 --contact-duration-s 0.001 --surface plate --restitution 0.681 "
      "--drop-height-m 0.564 --click-gain 0.27 --precursor-lead-s 0.0055 "
      "--precursor-gain-db -21 --echo-delay-s 0.0028 --echo-gain-db -8 --seed 147");
  ASSERT_GE(truth.size(), 5u);
  const auto json = ScratchPath("precursor.json");
  const auto analyzed =
      RunBouncecal("analyze '" + wav.string() + "' --json '" + json.string() + "'");
  ASSERT_EQ(analyzed.exit_status, 0) << analyzed.output;
  std::vector<std::pair<double, double>> errors;  // (onset - nearest bounce, stated sigma)
  const auto analysis = ReadJsonFile(json);
  for (const auto& impact : analysis["recordings"][0]["impacts"]) {
    if (!impact["sequence"].is_number()) continue;
    const double onset = impact["onset_s"].get<double>();
    double nearest = std::numeric_limits<double>::infinity();
    for (double t : truth) {
      if (std::fabs(onset - t) < std::fabs(nearest)) nearest = onset - t;
    }
    errors.emplace_back(nearest, impact["onset_uncertainty_s"].get<double>());
  }
  ASSERT_GE(errors.size(), 5u);
  // Intervals see the onsets less the recording's common offset: that of the most precisely
  // stated onset (the late bounces here are residual-only, stated +-1.9 ms).
  const auto reference =
      std::min_element(errors.begin(), errors.end(),
                       [](const auto& a, const auto& b) { return a.second < b.second; });
  const double offset = reference->first;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    const double error = errors[k].first - offset;
    // 0.5 ms: half the contact; 3 sigmas, since an onset that states its doubt is honest.
    EXPECT_FALSE(std::fabs(error) > 500e-6 && std::fabs(error) > 3 * errors[k].second)
        << "impact " << k + 1 << ": " << error * 1e6 << " us at a stated " << errors[k].second * 1e6
        << " us";
  }
}

// A drop rendered by `bouncecal synth` with `options` to the scratch file `name`.wav and
// analysed: its ball's impact times and the first sequence `analyze` finds (null where it fails).
struct AnalyzedSynthesis {
  std::vector<double> truth;
  nlohmann::json sequence;
};
AnalyzedSynthesis AnalyzeSynthesized(const std::string& name, const std::string& options) {
  const auto wav = ScratchPath(name + ".wav");
  AnalyzedSynthesis drop;
  drop.truth = SynthesizedBounceTimes(wav, options);
  drop.sequence = FirstSequenceOf(wav, name + ".json");
  return drop;
}

// eta-bar over impacts 1-3 from the exact onsets of the first five bounces.
double ExactEtaBarOfTheFirstThree(const std::vector<double>& truth) {
  double exact = 0;
  for (std::size_t k = 1; k <= 3; ++k) {
    const double e = (truth[k + 1] - truth[k]) / (truth[k] - truth[k - 1]);
    exact += (1 - e * e) / 3;
  }
  return exact;
}

// Whether `analyze` found a sequence of at least five members for a drop of at least five
// bounces, starting within first_within_s of its first bounce (on it, or on a sound before it).
::testing::AssertionResult FoundFromTheFirstBounce(const AnalyzedSynthesis& drop,
                                                   double first_within_s) {
  if (drop.sequence.is_null()) return ::testing::AssertionFailure() << "no sequence";
  if (drop.sequence["onsets_s"].size() < 5 || drop.truth.size() < 5) {
    return ::testing::AssertionFailure()
           << drop.sequence["onsets_s"].size() << " members of " << drop.truth.size() << " bounces";
  }
  const double first_s = drop.sequence["onsets_s"][0].get<double>();
  if (std::fabs(first_s - drop.truth[0]) >= first_within_s) {
    return ::testing::AssertionFailure()
           << "starts at " << first_s << " s, the drop at " << drop.truth[0] << " s";
  }
  return ::testing::AssertionSuccess();
}

// The sweep's rule for a silent wrong answer (silent_wrong_sweep.py): eta-bar off the exact
// onsets' by more than 0.002 and by more than 3 of its stated sigmas.
void ExpectNotSilentWrong(const nlohmann::json& sequence, const std::vector<double>& truth) {
  const double exact = ExactEtaBarOfTheFirstThree(truth);
  const double eta_bar = sequence["energy_loss_mean_first_n"].get<double>();
  const double sigma = sequence["energy_loss_mean_first_n_uncertainty"].get<double>();
  EXPECT_FALSE(std::fabs(eta_bar - exact) > 0.002 && std::fabs(eta_bar - exact) > 3 * sigma)
      << eta_bar << " +- " << sigma << " vs " << exact;
}

// An 8 kHz drop through a linear-phase recording chain and a 1.85 kHz band limit, 1 ms contacts
// on a counter, 12 dB SNR to the weakest bounce (the sweep's seed 101 #112): each filter rings
// before a sharp attack as well as after it (4.3 ms at this rate), and over the loud first
// bounce that ringing rose by the detector's threshold 3.07 ms before contact, an onset stated
// +-168 us. Once the response timing aligned two of the next four bounces (+-61 and +-95 us),
// eta-bar read 0.1793 +- 0.0007 against the exact onsets' 0.1755 (5.4 sigmas). Below 20 kHz, as
// in a transform codec's file, an onset that the alignment does not time and whose first
// millisecond stays 10 dB under the attack that follows states half the distance to that attack.
TEST(AnalyzeCli, AnOnsetInALinearPhaseChainsPreRingingStatesTheLaterAttack) {
  const auto [truth, sequence] = AnalyzeSynthesized(
      "prering",
      "--sample-rate-hz 8000 --contact-duration-s 0.001 --surface counter --restitution 0.908 "
      "--drop-height-m 0.548 --seed 113 --snr-db 12 --snr-reference weakest --adc linear-phase "
      "--click-gain 0.13 --band-limit-hz 1849");
  ASSERT_FALSE(sequence.is_null());
  ASSERT_GE(sequence["onsets_s"].size(), 6u);
  ASSERT_GE(truth.size(), 6u);
  ExpectOnsetsHonest(sequence, truth, 6, OffsetOfTheMostPreciselyStated(sequence, truth, 6));
}

// A 22 kHz drop of a ball with a 1 ms contact on a counter, a click 16 dB under each bounce 6.7 ms
// before it and an echo 8 ms after, 20 dB SNR to the weakest bounce and 50 Hz hum (the sweep's
// seed 808 #121). The click and the start of the 2nd bounce made one candidate, closed while its
// band was still rising into the bounce; the bounce's own candidate could not pick before that
// candidate's last peak, and found the rest of the rise 1.6 ms late at a stated 106 us: eta-bar
// 0.3362 +- 0.0005 against the exact onsets' 0.3341 (4.4 sigmas). An onset whose search the last
// peak of a still-rising candidate cut states half its search (onset_locator.cc).
TEST(AnalyzeCli, ASoundRisingIntoTheNextCandidateLeavesItsOnsetInDoubt) {
  const auto [truth, sequence] = AnalyzeSynthesized(
      "rising_into",
      "--sample-rate-hz 22050 --contact-duration-s 0.001 --surface counter --restitution 0.816 "
      "--drop-height-m 0.563 --seed 122 --snr-db 20 --snr-reference weakest --hum-hz 50 "
      "--hum-dbfs -20 --precursor-lead-s 0.0067 --precursor-gain-db -16 --echo-delay-s 0.0080 "
      "--echo-gain-db -5");
  ASSERT_FALSE(sequence.is_null());
  ASSERT_GE(sequence["onsets_s"].size(), 5u);
  ASSERT_GE(truth.size(), 5u);
  // The sequence starts at the first bounce.
  ASSERT_LT(std::fabs(sequence["onsets_s"][0].get<double>() - truth[0]), 1e-3);
  ExpectOnsetsHonest(sequence, truth, 5, OffsetOfTheMostPreciselyStated(sequence, truth, 5));
  ExpectNotSilentWrong(sequence, truth);
}

// A 48 kHz drop on a plate whose every bounce has a click 12 dB under it 2.1 ms before it
// (silent_wrong_sweep.py --precursors seed 920 #1): the first, loudest bounce's click rang into it
// and kept one candidate, timed on the click at a stated 32 us, while every later bounce, its
// click in the ringing before it, was timed on itself. eta-bar 0.2367 +- 0.0002 against the exact
// onsets' 0.2344 (12.8 sigmas, exit 0). The first flight's ratio has none before it to tell the
// two sounds apart, so such a first member states half the spacing (merged_alternatives.cc).
TEST(AnalyzeCli, AFirstBounceTimedOnItsClickStatesTheBounceAfterIt) {
  const auto drop = AnalyzeSynthesized(
      "first_on_click",
      "--sample-rate-hz 48000 --contact-duration-s 0.0004 --surface plate --restitution 0.875 "
      "--drop-height-m 0.364 --seed 2 --precursor-lead-s 0.0021 --precursor-gain-db -12.1 "
      "--level-jitter-db 3 --snr-db 40");
  ASSERT_TRUE(FoundFromTheFirstBounce(drop, 3e-3));
  ExpectOnsetsHonest(drop.sequence, drop.truth, 5,
                     OffsetOfTheMostPreciselyStated(drop.sequence, drop.truth, 5));
  ExpectNotSilentWrong(drop.sequence, drop.truth);
}

// The same pattern through a phone's gain stage: an AGC, then a look-ahead limiter at -1 dBFS,
// 96 kHz drops on a plate with a click 10-13 dB under each bounce 7 ms before it. The limiter
// brings the loud bounces down towards their clicks; the later, quieter ones are timed on
// themselves with their clicks merged (merged_alternatives.cc, each case's rule).
TEST(AnalyzeCli, LimitedBouncesTimedOnTheirClicksStateTheBounceAfterThem) {
  struct Case {
    const char* name;
    const char* options;
  };
  const Case cases[] = {
      // silent_wrong_sweep.py --limiter --precursors seed 957 #101 (AGC at 10.7 dB): the first
      // bounce's click rang into it and kept one candidate, timed on the click at a stated 19 us
      // with nothing recorded of the bounce: eta-bar 0.3310 +- 0.0001 against the exact onsets'
      // 0.3243 (68 sigmas, exit 0). A first member of unknown sound where every paired member is
      // on its bounce states half the spacing.
      {"limited_first",
       "--sample-rate-hz 96000 --contact-duration-s 0.0004 --surface plate --restitution 0.822 "
       "--drop-height-m 0.416 --seed 102 --precursor-lead-s 0.0072 --precursor-gain-db -12.7 "
       "--level-jitter-db 3 --snr-db 40 --adc linear-phase --limiter-lookahead-s 0.001 "
       "--limiter-release-s 0.02 --limiter-gain-db 10.7 --agc-target-dbfs -13.3 "
       "--agc-slew-db-per-s 3 --agc-level-time-s 0.3"},
      // Seed 959 #55 (AGC from 25.7 dB): the first four bounces, all limited, timed on their clicks
      // and aligned to one another (+-5 us) with nothing recorded of the bounces, the pairs putting
      // the rest on their bounces; the interval after the run 7 ms short: eta-bar 0.3894 +-
      // 0.0001 against 0.4025 (224 sigmas). The flight after the run states half the spacing.
      {"limited_run",
       "--sample-rate-hz 96000 --contact-duration-s 7e-05 --surface plate --restitution 0.773 "
       "--drop-height-m 0.452 --seed 56 --precursor-lead-s 0.0070 --precursor-gain-db -10.4 "
       "--level-jitter-db 3 --snr-db 40 --limiter-lookahead-s 0.0005 --limiter-release-s 0.06 "
       "--limiter-gain-db 25.7 --agc-target-dbfs -12.8 --agc-slew-db-per-s 6 "
       "--agc-level-time-s 0.1"},
      // Seed 956 #30 (a fixed 11.2 dB, the click 11.8 dB under each bounce 5.4 ms before it): the
      // first click and bounce both at the ceiling, so the bounce neither rose a threshold over
      // the click's ringing nor stood 6 dB over its first millisecond, and only two members had
      // their clicks merged (no pairs weighed): the first member on its click at a stated 18 us,
      // eta-bar 0.6370 +- 0.0000 against 0.6340 (88 sigmas). Its bounce's fresh attack at the
      // spacing (Impact::later_rise_s) puts it on the click of the pair.
      {"limited_click_first",
       "--sample-rate-hz 96000 --contact-duration-s 7e-05 --surface plate --restitution 0.605 "
       "--drop-height-m 0.597 --seed 31 --precursor-lead-s 0.0054 --precursor-gain-db -11.8 "
       "--level-jitter-db 3 --snr-db 40 --adc linear-phase --limiter-lookahead-s 0.005 "
       "--limiter-release-s 0.2 --limiter-gain-db 11.2"},
      // Seed 956 #84 (22 kHz, an AGC from 25.4 dB): members 0-3 on their clicks, 4 on, the rest
      // on their bounces with the clicks merged; the interval from the 4th to the 5th 5.1 ms
      // short at a stated 0.2 ms, eta-bar 26 sigmas off. The 4th's fresh attack at the spacing.
      {"limited_click_run",
       "--sample-rate-hz 22050 --contact-duration-s 3.5e-05 --surface plate --restitution 0.855 "
       "--drop-height-m 0.440 --seed 85 --precursor-lead-s 0.0053 --precursor-gain-db -9.6 "
       "--level-jitter-db 3 --snr-db 40 --limiter-lookahead-s 0.005 --limiter-release-s 0.06 "
       "--limiter-gain-db 25.4 --agc-target-dbfs -22.8 --agc-slew-db-per-s 6 "
       "--agc-level-time-s 0.1"},
      // Seed 960 #178 (22 kHz counter, an AGC from 25 dB, clicks 7.5 ms ahead): members 0-3 on
      // their clicks, aligned to one another by the response timing, the rest on their bounces
      // with two clicks merged (no pairs weighed): eta-bar 100 sigmas off. The run's end.
      {"limited_aligned_run",
       "--sample-rate-hz 22050 --contact-duration-s 3.5e-05 --surface counter --restitution 0.766 "
       "--drop-height-m 0.249 --seed 179 --precursor-lead-s 0.0075 --precursor-gain-db -10.9 "
       "--level-jitter-db 3 --snr-db 40 --limiter-lookahead-s 0.0005 --limiter-release-s 0.02 "
       "--limiter-gain-db 25.0 --agc-target-dbfs -14.0 --agc-slew-db-per-s 6 "
       "--agc-level-time-s 0.1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto drop = AnalyzeSynthesized(c.name, c.options);
    ASSERT_TRUE(FoundFromTheFirstBounce(drop, 8e-3));
    ExpectNotSilentWrong(drop.sequence, drop.truth);
  }
}

// The leading run of the case above timed on its clicks (seed 960 #178) is doubted as the flight
// after it (incoming_flight_uncertainty_s); calibrate must read that doubt back from the JSON and
// from the CSV alike, or the fit's interval would narrow by it.
TEST(AnalyzeCli, TheFlightAfterALimitedRunReachesCalibrateFromJsonAndCsv) {
  const auto wav = ScratchPath("flight_run.wav");
  SynthesizedBounceTimes(
      wav,
      "--sample-rate-hz 22050 --contact-duration-s 3.5e-05 --surface counter --restitution 0.766 "
      "--drop-height-m 0.249 --seed 179 --precursor-lead-s 0.0075 --precursor-gain-db -10.9 "
      "--level-jitter-db 3 --snr-db 40 --limiter-lookahead-s 0.0005 --limiter-release-s 0.02 "
      "--limiter-gain-db 25.0 --agc-target-dbfs -14.0 --agc-slew-db-per-s 6 "
      "--agc-level-time-s 0.1");
  const auto json = ScratchPath("flight_run.json"), csv = ScratchPath("flight_run.csv");
  const auto analyzed = RunBouncecal("analyze '" + wav.string() + "' --json '" + json.string() +
                                     "' --csv '" + csv.string() + "'");
  ASSERT_EQ(analyzed.exit_status, 0) << analyzed.output;
  const auto flights =
      ReadJsonFile(json)["recordings"][0]["sequences"][0]["incoming_flight_uncertainty_s"]
          .get<std::vector<double>>();
  // Half the 7.5 ms spacing, on the flight after the run of four.
  ASSERT_GE(flights.size(), 5u);
  EXPECT_NEAR(flights[4], 0.5 * 7.5e-3, 0.5e-3);
  const auto eta_bar_line = [](const fs::path& input) {
    const auto fit = RunBouncecal("calibrate '" + input.string() + "' --ball steel-10mm");
    EXPECT_EQ(fit.exit_status, 0) << fit.output;
    const auto at = fit.output.find("eta-bar(first 3)");
    return at == std::string::npos ? std::string()
                                   : fit.output.substr(at, fit.output.find('\n', at) - at);
  };
  const std::string from_json = eta_bar_line(json);
  EXPECT_FALSE(from_json.empty());
  EXPECT_EQ(eta_bar_line(csv), from_json);
}

// A 32 kHz drop on a counter in a 0.29 s reverb with 60 Hz hum at -27 dBFS (the sweep's seed 101
// #68): its 5th bounce is buried in the tail of the 4th, and the only sound the tracking finds
// where it is due is a swell of that tail 7.0 ms after it, found by the ringing residual alone and
// stated +-1.3 ms (5.3 sigmas; eta-bar 0.6866 +- 0.0099 against the exact onsets' 0.7180, exit
// 0). The sequence's own flights put the bounce 6.8 ms before that sound, beyond what 3 % scatter
// of e and the stated sigmas explain, so the member states half the distance too
// (docs/detector.md, "A residual-only member that misses its prediction").
TEST(AnalyzeCli, AResidualOnlyMemberFarFromItsPredictionStatesItsDoubt) {
  const auto [truth, sequence] = AnalyzeSynthesized(
      "buried",
      "--sample-rate-hz 32000 --contact-duration-s 7e-05 --surface counter --restitution 0.531 "
      "--drop-height-m 0.375 --seed 69 --snr-db 30 --snr-reference weakest --click-gain 0.15 "
      "--reverb-rt60-s 0.29 --hum-hz 60 --hum-dbfs -27");
  ASSERT_FALSE(sequence.is_null());
  ASSERT_GE(sequence["onsets_s"].size(), 5u);
  ASSERT_GE(truth.size(), 5u);
  ExpectOnsetsHonest(sequence, truth, 5, 0.0);
  const double exact = ExactEtaBarOfTheFirstThree(truth);
  const double eta_bar = sequence["energy_loss_mean_first_n"].get<double>();
  const double sigma = sequence["energy_loss_mean_first_n_uncertainty"].get<double>();
  EXPECT_LE(std::fabs(eta_bar - exact), 3 * sigma) << eta_bar << " +- " << sigma << " vs " << exact;
}

// A 22 kHz drop whose every bounce has a click 11 dB under it 5.9 ms before (the sweep's seed 53
// #115): the click rings into its bounce and keeps one candidate open, so four of the first five
// members were timed on their clicks and the fifth on its bounce, the click merged as its
// precursor, all stated +-23-65 us: eta-bar 0.4359 +- 0.0002 against the exact onsets' 0.4480.
// The sequence takes the merged click that continues its ratios, in a WAV as in a codec's file
// (merged_alternatives.h).
TEST(AnalyzeCli, AMemberTimedOnItsBounceTakesThePrecursorItsNeighboursWereTimedOn) {
  const auto [truth, sequence] = AnalyzeSynthesized(
      "precursors",
      "--sample-rate-hz 22050 --contact-duration-s 7e-05 --surface plate --restitution 0.743 "
      "--drop-height-m 0.465 --seed 116 --snr-db 45 --snr-reference first --adc linear-phase "
      "--hum-hz 50 --hum-dbfs -24 --precursor-lead-s 0.0059 --precursor-gain-db -11");
  ASSERT_FALSE(sequence.is_null());
  ASSERT_GE(truth.size(), 5u);
  // The sequence starts at the first bounce (timed on its click, 5.9 ms before it).
  ASSERT_LT(std::fabs(sequence["onsets_s"][0].get<double>() - truth[0]), 10e-3);
  ExpectNotSilentWrong(sequence, truth);
}

// Drops of the sweep's --precursors kind (silent_wrong_sweep.py, seed 7): a click 9-14 dB under
// every bounce and a few ms before it. #63 (96 kHz, clicks 10.5 dB under, 5.9 ms before): the
// first four members were timed on their clicks, one candidate each with nothing recorded of the
// bounce, the rest on their bounces; eta-bar 0.4366 +- 0.0048 against 0.4524. #24 (44.1 kHz
// counter, 9.2 dB under, 7.9 ms before): the first four on their clicks, the bounces merged as
// their echoes, the next two on their bounces; 0.5216 +- 0.0043 against 0.5390. The sequence
// times every pair on one sound (merged_alternatives.h).
TEST(AnalyzeCli, MembersTimedSomeOnTheirClicksSomeOnTheirBouncesAreTimedOnOne) {
  for (const std::string options :
       {"--sample-rate-hz 96000 --contact-duration-s 7e-05 --surface plate --restitution 0.740 "
        "--drop-height-m 0.266 --seed 64 --precursor-lead-s 0.0059 --precursor-gain-db -10.5 "
        "--level-jitter-db 3 --snr-db 40",
        "--sample-rate-hz 44100 --contact-duration-s 7e-05 --surface counter --restitution 0.679 "
        "--drop-height-m 0.569 --seed 25 --precursor-lead-s 0.0079 --precursor-gain-db -9.2 "
        "--level-jitter-db 3 --snr-db 40 --adc linear-phase"}) {
    const auto [truth, sequence] = AnalyzeSynthesized("clicks", options);
    ASSERT_FALSE(sequence.is_null()) << options;
    ASSERT_GE(truth.size(), 5u);
    ASSERT_LT(std::fabs(sequence["onsets_s"][0].get<double>() - truth[0]), 10e-3) << options;
    ExpectNotSilentWrong(sequence, truth);
  }
}

TEST(AnalyzeCli, ChannelOutsideTheFileIsABadOption) {
  const auto drop = SyntheticDrop("mono.wav", 7, 0.2);
  const auto result = RunBouncecal("analyze '" + drop.string() + "' --channel 3");
  EXPECT_EQ(result.exit_status, 3) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
