#include "bouncecal/calibrate/impact_times.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::calibrate {
namespace {

using bouncecal::testing::ScratchPath;

std::filesystem::path WriteTemp(const std::string& name, const std::string& content) {
  const auto path = ScratchPath(name);
  std::ofstream(path) << content;
  return path;
}

TEST(ImpactTimesOptions, DefaultsAreValid) {
  const ImpactTimesOptions options;
  EXPECT_GT(options.default_uncertainty_s, 0);
  EXPECT_GE(options.min_impacts, 2);
}

TEST(ReadImpactTimes, CsvWithHeaderUncertaintiesAndTwoSequences) {
  const auto path = WriteTemp("two.csv",
                              "# two drops\nonset_s,onset_uncertainty_s,sequence\n"
                              "0.202,1e-5,1\n0.55,2e-5,1\n0.80,1e-5,1\n"
                              "5.1,,2\n5.4,,2\n5.6,,2\n5.7,,2\n");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 2u);
  EXPECT_EQ(sequences[0].impacts.size(), 3u);
  EXPECT_DOUBLE_EQ(sequences[0].impacts[1].uncertainty_s, 2e-5);
  EXPECT_EQ(sequences[1].impacts.size(), 4u);
  EXPECT_DOUBLE_EQ(sequences[1].impacts[0].uncertainty_s,
                   ImpactTimesOptions{}.default_uncertainty_s);
}

TEST(ReadImpactTimes, AnalyzeJsonTakesUncertaintiesFromTheImpactList) {
  const auto path = WriteTemp("analyze.json", R"({"file": "/x/drop.wav", "sample_rate_hz": 48000,
    "channel": 0,
    "impacts": [{"onset_s": 0.1, "onset_uncertainty_s": 3e-6, "peak_dbfs": -3, "sequence": 0},
                {"onset_s": 0.4, "onset_uncertainty_s": 4e-6, "peak_dbfs": -6, "sequence": 0},
                {"onset_s": 0.6, "onset_uncertainty_s": 5e-6, "peak_dbfs": -9, "sequence": 0},
                {"onset_s": 2.0, "onset_uncertainty_s": 5e-6, "peak_dbfs": -9, "sequence": null}],
    "rejected_events": [],
    "sequences": [{"onsets_s": [0.1, 0.4, 0.6], "intervals_s": [0.3, 0.2]}]})");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 1u);
  EXPECT_EQ(sequences[0].source, "drop.wav#1");
  ASSERT_EQ(sequences[0].impacts.size(), 3u);
  EXPECT_DOUBLE_EQ(sequences[0].impacts[2].uncertainty_s, 5e-6);
}

// A leading run doubted as a whole states the flight after it (TimedImpact::
// incoming_flight_uncertainty_s): calibrate must read it back, or its interval would narrow by
// the switch's doubt. None is taken into a sequence's first onset, and a file written before the
// field states none.
TEST(ReadImpactTimes, AnalyzeJsonKeepsTheFlightUncertaintiesOfEachSequence) {
  const auto path = WriteTemp("flights.json", R"({"file": "/x/drop.wav",
    "impacts": [{"onset_s": 0.1, "onset_uncertainty_s": 3e-6, "sequence": 0},
                {"onset_s": 0.4, "onset_uncertainty_s": 4e-6, "sequence": 0},
                {"onset_s": 0.6, "onset_uncertainty_s": 5e-6, "sequence": 0},
                {"onset_s": 1.1, "onset_uncertainty_s": 3e-6, "sequence": 1},
                {"onset_s": 1.4, "onset_uncertainty_s": 4e-6, "sequence": 1},
                {"onset_s": 1.6, "onset_uncertainty_s": 5e-6, "sequence": 1}],
    "sequences": [{"onsets_s": [0.1, 0.4, 0.6], "incoming_flight_uncertainty_s": [1, 0, 2.5e-3]},
                  {"onsets_s": [1.1, 1.4, 1.6]}]})");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 2u);
  const auto flights = [](const MeasuredSequence& sequence) {
    std::vector<double> sigmas;
    for (const auto& impact : sequence.impacts)
      sigmas.push_back(impact.incoming_flight_uncertainty_s);
    return sigmas;
  };
  EXPECT_EQ(flights(sequences[0]), (std::vector<double>{0, 0, 2.5e-3}));
  EXPECT_EQ(flights(sequences[1]), (std::vector<double>{0, 0, 0}));
  EXPECT_DOUBLE_EQ(sequences[0].impacts[2].uncertainty_s, 5e-6);
  // A negative one is refused naming the file, as the CSV reader refuses it.
  const auto negative = WriteTemp("negative_flight.json", R"({"file": "/x/drop.wav",
    "impacts": [], "sequences": [{"onsets_s": [0.1, 0.4, 0.6],
                                  "incoming_flight_uncertainty_s": [0, -1e-3, 0]}]})");
  try {
    ReadImpactTimes(negative);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(negative.string()), std::string::npos) << error.what();
  }
}

// The same through `bouncecal analyze --csv`'s columns (any order, by name).
TEST(ReadImpactTimes, AnalyzeCsvKeepsTheFlightUncertainties) {
  const auto path = WriteTemp("flights.csv",
                              "sequence,onset_s,onset_uncertainty_s,incoming_flight_uncertainty_s\n"
                              "0,0.1,3e-6,0.000000000\n0,0.4,4e-6,0.000000000\n"
                              "0,0.6,5e-6,0.002500000\n");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 1u);
  ASSERT_EQ(sequences[0].impacts.size(), 3u);
  EXPECT_EQ(sequences[0].impacts[1].incoming_flight_uncertainty_s, 0.0);
  EXPECT_EQ(sequences[0].impacts[2].incoming_flight_uncertainty_s, 2.5e-3);
  EXPECT_THROW(ReadImpactTimes(WriteTemp("bad_flight.csv",
                                         "onset_s,incoming_flight_uncertainty_s\n0.1,0\n0.4,-1\n")),
               InputError);
}

// `bouncecal analyze --csv` of two recordings: each numbers its sequences from 0, and an impact
// in no sequence has the column blank. Each recording's sequence stays its own, named as its
// analysis names it (a name with a comma in quotes), and the stray impact joins none (taken into
// sequence 0 before, a stray sound of the detector suite's clipping.wav turned its eta-bar 0.5505
// +- 0.0003 into -0.04).
TEST(ReadImpactTimes, AnalyzeCsvKeepsRecordingsApartAndStrayImpactsOut) {
  const auto path =
      WriteTemp("two_recordings.csv",
                "file,channel,sequence,k,onset_s,onset_uncertainty_s\n"
                "/x/a.wav,0,0,1,0.1,3e-6\n/x/a.wav,0,,,0.25,3e-6\n"
                "/x/a.wav,0,0,2,0.4,3e-6\n/x/a.wav,0,0,3,0.6,3e-6\n"
                "\"/x/b, second.wav\",0,0,1,0.2,3e-6\n\"/x/b, second.wav\",0,0,2,0.5,3e-6\n"
                "\"/x/b, second.wav\",0,0,3,0.7,3e-6\n");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 2u);
  EXPECT_EQ(sequences[0].source, "a.wav#1");
  EXPECT_EQ(sequences[1].source, "b, second.wav#1");
  for (const auto& sequence : sequences) EXPECT_EQ(sequence.impacts.size(), 3u) << sequence.source;
  EXPECT_EQ(sequences[0].impacts[1].onset_s, 0.4);
}

// One recording entry as bouncecal analyze --json writes it, with three impacts starting at t0.
std::string RecordingEntry(const std::string& file, double t0) {
  const auto t = [t0](double dt) { return std::to_string(t0 + dt); };
  return R"({"file": ")" + file + R"(", "impacts": [
      {"onset_s": )" +
         t(0) + R"(, "onset_uncertainty_s": 3e-6, "sequence": 0},
      {"onset_s": )" +
         t(0.3) + R"(, "onset_uncertainty_s": 4e-6, "sequence": 0},
      {"onset_s": )" +
         t(0.5) + R"(, "onset_uncertainty_s": 7e-6, "sequence": 0}],
    "sequences": [{"onsets_s": [)" +
         t(0) + ", " + t(0.3) + ", " + t(0.5) + "]}]}";
}

TEST(ReadImpactTimes, AnalysisFormatOfSeveralRecordingsGivesEverySequenceInOrder) {
  const auto path =
      WriteTemp("analysis.json",
                std::string(R"({"format": "bouncecal-analysis/1", "recordings": [)") +
                    RecordingEntry("/x/a.wav", 0.1) + ", " + RecordingEntry("/x/b.wav", 1.1) +
                    R"(], "summary": {"recordings": 2, "energy_loss_mean": null}})");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 2u);
  EXPECT_EQ(sequences[0].source, "a.wav#1");
  EXPECT_EQ(sequences[1].source, "b.wav#1");
  EXPECT_DOUBLE_EQ(sequences[1].impacts[0].onset_s, 1.1);
  EXPECT_DOUBLE_EQ(sequences[1].impacts[2].uncertainty_s, 7e-6);
}

TEST(ReadImpactTimes, TheArrayWrittenBeforeTheFormatFieldIsStillRead) {
  // Appended, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that insert.
  std::string legacy = "[";
  legacy.append(RecordingEntry("/x/a.wav", 0.1))
      .append(", ")
      .append(RecordingEntry("/x/b.wav", 2.1))
      .append(R"(, {"summary": {}}])");
  const auto path = WriteTemp("legacy.json", legacy);
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 2u);
  EXPECT_EQ(sequences[1].source, "b.wav#1");
}

TEST(ReadImpactTimes, ALaterAnalysisVersionIsRefusedNamingIt) {
  const auto path = WriteTemp("future.json",
                              std::string(R"({"format": "bouncecal-analysis/2", "recordings": [)") +
                                  RecordingEntry("/x/a.wav", 0.1) + "]}");
  try {
    ReadImpactTimes(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bouncecal-analysis/2"), std::string::npos)
        << error.what();
  }
}

TEST(ReadImpactTimes, AFitResultIsNotTakenForAnalyzeOutput) {
  // A calibrate --json document has a "sequences" key too, with fitted, not measured, entries.
  const auto path = WriteTemp("fit.json", R"({"format": "bouncecal-fit/1", "sequences": [
      {"source": "a.wav#1", "measured": {}, "simulated_onsets_s": [0.1, 0.4, 0.6]}]})");
  try {
    ReadImpactTimes(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("not analyze output"), std::string::npos)
        << error.what();
  }
}

TEST(ReadImpactTimes, SynthesizerTruthCsvKeepsOnlyBallImpactsPerDrop) {
  // The columns bouncecal synth --truth writes: other events (kind knock, drop -1) are skipped.
  const auto path = WriteTemp("truth.csv",
                              "onset_s,impact_speed_mps,kind,drop\n0.35,0.5,knock,-1\n"
                              "0.5,1.98,ball_impact,0\n0.76,1.28,ball_impact,0\n"
                              "0.93,0.83,ball_impact,0\n");
  const auto sequences = ReadImpactTimes(path);
  ASSERT_EQ(sequences.size(), 1u);
  ASSERT_EQ(sequences[0].impacts.size(), 3u);
  EXPECT_DOUBLE_EQ(sequences[0].impacts[0].onset_s, 0.5);
  // impact_speed_mps is not an uncertainty: the default applies.
  EXPECT_DOUBLE_EQ(sequences[0].impacts[0].uncertainty_s,
                   ImpactTimesOptions{}.default_uncertainty_s);
}

TEST(ReadImpactTimes, MalformedRowNamesTheLine) {
  const auto path = WriteTemp("bad.csv", "0.1\n0.4\nfoo bar\n0.6\n");
  try {
    ReadImpactTimes(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("line 3"), std::string::npos) << error.what();
  }
}

TEST(ReadImpactTimes, TooFewImpactsIsAnInputError) {
  const auto path = WriteTemp("short.csv", "0.1\n0.4\n");
  EXPECT_THROW(ReadImpactTimes(path), InputError);
}

TEST(ReadImpactTimes, JsonWithoutSequencesIsAnInputError) {
  const auto path = WriteTemp("other.json", R"({"law": "walton-braun"})");
  EXPECT_THROW(ReadImpactTimes(path), InputError);
}

}  // namespace
}  // namespace bouncecal::calibrate
