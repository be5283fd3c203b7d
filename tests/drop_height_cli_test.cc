// The researcher's protocol on the command line: one drop height per recording (repeated
// --drop-height-m, --manifest), heights checked against the recording, and what is said when
// they disagree (docs/calibration.md, "Several drops and heights").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "synthetic_drop.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

// The table-damped steel drop of synthetic_drop.h (the analyze CLI tests' drop), e = 0.648.
fs::path SyntheticDrop(const std::string& name, double height_m, std::uint64_t seed) {
  return WriteTableDampedDrop(ScratchPath(name), height_m, seed);
}

int Lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

TEST(DropHeightCli, AHeightTheBouncesContradictIsFlaggedByAnalyzeAndRefusedByCalibrate) {
  // Fr4nci's Audio_1.wav misses its first bounce(s): with the 1.5 m release, e_1 = 0.50 beside
  // e_2.. = 0.81 (docs/recordings.md).
  const fs::path audio_1 = SharedDir() / "recordings" / "fr4nci-rimbalzi" / "Audio_1.wav";
  if (!fs::exists(audio_1)) GTEST_SKIP() << audio_1 << " is not here";
  const auto analyze = RunBouncecal("analyze " + audio_1.string() + " --drop-height-m 1.5");
  EXPECT_EQ(analyze.exit_status, 0) << analyze.output;
  EXPECT_NE(analyze.output.find("first impact was probably missed or the height is wrong"),
            std::string::npos)
      << analyze.output;
  EXPECT_NE(analyze.output.find("correct --drop-height-m"), std::string::npos) << analyze.output;
  // Its low floor lets stray sounds through: 9 of its impacts fit no sequence. They were 9 of 17,
  // most of them, and it warned; its 9th and 10th bounces, rises of half the threshold that stand
  // out of the noise under the ringing, now join the sequence (10 impacts; 12 of 21 since a
  // later in-ringing sound must also raise the residual as much to take a merged pair's onset),
  // so the strays are no longer most of what it heard and it does not (the warning's rule: more
  // left out than in).
  EXPECT_NE(analyze.output.find("21 impacts, 1 sequence(s)"), std::string::npos) << analyze.output;
  EXPECT_EQ(analyze.output.find("fit no bounce sequence"), std::string::npos) << analyze.output;

  const auto calibrate = RunBouncecal("calibrate " + audio_1.string() + " --drop-height-m 1.5");
  EXPECT_EQ(calibrate.exit_status, 3) << calibrate.output;
  EXPECT_NE(calibrate.output.find("e_1 = 0.4"), std::string::npos) << calibrate.output;
  EXPECT_NE(calibrate.output.find("these bounces imply a release from"), std::string::npos)
      << calibrate.output;
  EXPECT_EQ(Lines(calibrate.output), 1) << calibrate.output;

  // Its companion at its own 2.50 m is consistent: no such warning.
  const fs::path audio = SharedDir() / "recordings" / "fr4nci-rimbalzi" / "Audio.wav";
  const auto consistent = RunBouncecal("analyze " + audio.string() + " --drop-height-m 2.5");
  EXPECT_EQ(consistent.exit_status, 0) << consistent.output;
  EXPECT_EQ(consistent.output.find("probably missed"), std::string::npos) << consistent.output;
  // Its 5 strays among 17 impacts are no reason to doubt the sequence: no warning.
  EXPECT_EQ(consistent.output.find("fit no bounce sequence"), std::string::npos)
      << consistent.output;
}

TEST(DropHeightCli, AnalyzeRefusesAReboundAboveTheReleaseAsCalibrateDoes) {
  const auto wav = SyntheticDrop("rebound.wav", 0.2, 11);
  const auto json = ScratchPath("rebound.json");
  fs::remove(json);
  // The first rebound rises to 0.2 * 0.42 = 0.084 m.
  const auto result =
      RunBouncecal("analyze " + wav.string() + " --drop-height-m 0.05 --json " + json.string());
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("first rebound rose to 0.08"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("omit --drop-height-m"), std::string::npos) << result.output;
  EXPECT_EQ(Lines(result.output), 1) << result.output;
  EXPECT_FALSE(fs::exists(json));
}

TEST(DropHeightCli, EachRecordingTakesItsOwnHeightInOrderOrFromAManifest) {
  const auto low = SyntheticDrop("low.wav", 0.2, 12);
  const auto high = SyntheticDrop("high.wav", 0.4, 13);
  const auto json = ScratchPath("heights.json");
  const auto analyze =
      RunBouncecal("analyze " + low.string() + " " + high.string() +
                   " --drop-height-m 0.2 --drop-height-m 0.4 --json " + json.string());
  ASSERT_EQ(analyze.exit_status, 0) << analyze.output;
  const auto document = ReadJsonFile(json);
  EXPECT_EQ(document["recordings"][0]["drop_height_m"], 0.2);
  EXPECT_EQ(document["recordings"][1]["drop_height_m"], 0.4);
  EXPECT_EQ(document["recordings"][1]["sequences"][0]["drop_height_m"], 0.4);
  EXPECT_TRUE(document["recordings"][1]["sequences"][0]["drop_height_check"]["consistent"]);

  // Jointly: the per-sequence heights are recorded in the fit and the card.
  const auto fit = ScratchPath("fit.json"), card = ScratchPath("card.json");
  const auto calibrate =
      RunBouncecal("calibrate " + low.string() + " " + high.string() +
                   " --drop-height-m 0.2 --drop-height-m 0.4 --ball steel-10mm --json " +
                   fit.string() + " --card " + card.string());
  ASSERT_EQ(calibrate.exit_status, 0) << calibrate.output;
  EXPECT_NE(calibrate.output.find("drop heights per recording"), std::string::npos)
      << calibrate.output;
  const auto fitted = ReadJsonFile(fit);
  EXPECT_EQ(fitted["sequences"][0]["drop_height_m"], 0.2);
  EXPECT_EQ(fitted["sequences"][1]["drop_height_m"], 0.4);
  const auto written = ReadJsonFile(card);
  EXPECT_EQ(written["fit"]["release"], "per-recording");
  EXPECT_EQ(written["recordings"][1]["drop_height_m"], 0.4);

  // The same protocol as a manifest (paths relative to it) fits to the same gamma_n.
  const auto manifest = ScratchPath("drops.csv");
  std::ofstream(manifest) << "recording,drop_height_m\nlow.wav,0.2\nhigh.wav,0.4\n";
  const auto from_manifest = ScratchPath("manifest_fit.json");
  const auto listed = RunBouncecal("calibrate --manifest " + manifest.string() +
                                   " --ball steel-10mm --json " + from_manifest.string());
  ASSERT_EQ(listed.exit_status, 0) << listed.output;
  EXPECT_EQ(ReadJsonFile(from_manifest)["parameters"], fitted["parameters"]);

  // Two heights for three recordings: which is whose? Refused before anything is read.
  const auto mismatch = RunBouncecal("calibrate " + low.string() + " " + high.string() + " " +
                                     low.string() + " --drop-height-m 0.2 --drop-height-m 0.4");
  EXPECT_EQ(mismatch.exit_status, 3) << mismatch.output;
  EXPECT_NE(mismatch.output.find("--drop-height-m is given 2 times for 3 recordings"),
            std::string::npos)
      << mismatch.output;
  EXPECT_EQ(Lines(mismatch.output), 1) << mismatch.output;
}

TEST(DropHeightCli, AShortDropWithItsHeightIsToldToLowerFirstNotToGiveTheHeight) {
  // A steel-on-lead drop (e = 0.5) from 0.30 m of which three impacts were heard.
  const auto times = ScratchPath("lead.csv");
  const double fall = 0.2473;  // sqrt(2 * 0.30 / 9.81)
  std::ofstream(times) << "onset_s\n"
                       << 0.5 << "\n"
                       << 0.5 + fall << "\n"
                       << 0.5 + 1.5 * fall << "\n";
  // Without --first the default 3 falls to the 2 losses the recording gives, and says so; the
  // card records the count.
  const auto card = ScratchPath("lead_card.json");
  const auto fallback =
      RunBouncecal("calibrate " + times.string() +
                   " --drop-height-m 0.30 --ball steel-10mm --card " + card.string());
  EXPECT_EQ(fallback.exit_status, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("lead.csv: 3 impacts, eta-bar(first 2) = 0.7500"),
            std::string::npos)
      << fallback.output;
  EXPECT_NE(fallback.output.find("WARNING: recording lead.csv gives 2 energy losses, fewer than "
                                 "the 3 eta-bar averages by default"),
            std::string::npos)
      << fallback.output;
  EXPECT_NE(fallback.output.find("or give --first 2 for that many in every recording"),
            std::string::npos)
      << fallback.output;
  const auto written = ReadJsonFile(card);
  EXPECT_EQ(written["fit"]["first_n"], 3);
  EXPECT_EQ(written["recordings"][0]["first_n"], 2);
  // Asked for 3, it is refused and told what would help.
  const auto result =
      RunBouncecal("calibrate " + times.string() + " --drop-height-m 0.30 --first 3");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("gives 2 energy losses but --first 3 needs that many; set --first "
                               "to 2 or use a recording with more audible impacts"),
            std::string::npos)
      << result.output;
  EXPECT_EQ(result.output.find("give --drop-height-m"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
