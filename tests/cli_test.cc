#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "bouncecal/version.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

// Standard output alone (stderr discarded), to check what a pipe such as `| jq` would read.
std::string StdoutOf(const std::string& arguments) {
  const std::string command = std::string(BOUNCECAL_EXECUTABLE) + " " + arguments + " 2>/dev/null";
  std::string text;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return text;
  std::array<char, 4096> buffer{};
  size_t got = 0;
  while ((got = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), got);
  pclose(pipe);
  return text;
}

const std::string kSteelCsv = (SourceDir() / "samples/steel_ball_h0.2m.csv").string();

// A material card calibrated on the shipped sample (written once per test process, in a folder
// of the process: ctest runs each test in its own process, in parallel, and a shared folder let
// one test's calibrate truncate the card another test was reading).
fs::path Card() {
  static const ScratchFolder folder("card");
  static const fs::path card = [] {
    const auto path = folder / "card.json";
    const auto result =
        RunBouncecal("calibrate " + kSteelCsv + " --ball steel-10mm --drop-height-m 0.2 --card " +
                     path.string());
    EXPECT_EQ(result.exit_status, 0) << result.output;
    return path;
  }();
  return card;
}

TEST(Cli, VersionPrintsTheProjectVersion) {
  const auto result = RunBouncecal("version");
  EXPECT_EQ(result.exit_status, 0);
  EXPECT_NE(result.output.find("bouncecal 0."), std::string::npos) << result.output;
}

TEST(Cli, VersionFlagPrintsTheSameLineAsTheVersionCommand) {
  const auto flag = RunBouncecal("--version");
  EXPECT_EQ(flag.exit_status, 0) << flag.output;
  EXPECT_EQ(flag.output, "bouncecal " + std::string(Version()) + "\n");
  EXPECT_EQ(flag.output, RunBouncecal("version").output);
}

TEST(Cli, UnknownSubcommandIsAUsageError) {
  const auto result = RunBouncecal("frobnicate");
  EXPECT_EQ(result.exit_status, 3) << result.output;
}

// `--json -` puts the document, and only it, on standard output: the table goes to stderr, so
// the output parses as one JSON document.
TEST(Cli, JsonDashWritesOnlyTheDocumentToStandardOutput) {
  const std::string text = StdoutOf("simulate drop --gamma 0.5 --json -");
  const auto document = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(document.is_discarded()) << text;
  EXPECT_EQ(document["format"], "bouncecal-drop/1");
  EXPECT_GT(document["impacts"].size(), 3u);
  // The same bytes as the file the same command writes.
  const auto file = ScratchPath("drop.json");
  ASSERT_EQ(RunBouncecal("simulate drop --gamma 0.5 --quiet --json " + file.string()).exit_status,
            0);
  EXPECT_EQ(text, ReadFileText(file));
  EXPECT_FALSE(fs::exists("-")) << "a file named '-' was written";
}

TEST(Cli, TwoOutputsOnStandardOutputAreRefusedNamingBoth) {
  const auto result = RunBouncecal(
      "simulate drop --gamma 0.5 --json - --trajectory - --trajectory-interval-s 1e-3");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("--json"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--trajectory"), std::string::npos) << result.output;
}

// An old spelling is a hidden alias for one release: the same drop, and one note on stderr.
TEST(Cli, OldSpellingGivesTheSameResultWithADeprecationNote) {
  const std::string common = "simulate drop --quiet --gamma 0.4 --json - ";
  const auto old_spelling = RunBouncecal(common + "--drop-height 0.3 --diameter 0.02");
  ASSERT_EQ(old_spelling.exit_status, 0) << old_spelling.output;
  EXPECT_NE(old_spelling.output.find("--drop-height is deprecated"), std::string::npos)
      << old_spelling.output;
  EXPECT_NE(old_spelling.output.find("use --drop-height-m"), std::string::npos)
      << old_spelling.output;
  const std::string new_text = StdoutOf(common + "--drop-height-m 0.3 --diameter-m 0.02");
  EXPECT_EQ(StdoutOf(common + "--drop-height 0.3 --diameter 0.02"), new_text);
  const auto parsed = nlohmann::json::parse(new_text);
  EXPECT_EQ(parsed["drop_height_m"], 0.3);
  EXPECT_EQ(parsed["ball"]["diameter_m"], 0.02);
  // The old spelling is not offered in --help.
  const auto help = RunBouncecal("simulate drop --help");
  EXPECT_NE(help.output.find("--drop-height-m"), std::string::npos);
  EXPECT_EQ(help.output.find("--drop-height "), std::string::npos) << help.output;
}

TEST(Cli, OldAndNewSpellingOfOneQuantityTogetherAreRefused) {
  const auto result = RunBouncecal("simulate drop --drop-height-m 0.2 --drop-height 0.3");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("one option"), std::string::npos) << result.output;
}

TEST(Cli, SynthRefusesAnOutputNameThatChoosesNoFormatAndWritesNothing) {
  const auto mp3 = ScratchPath("drop.mp3");
  const auto result = RunBouncecal("synth -o " + mp3.string());
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find(".wav or .flac"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(mp3));
}

TEST(Cli, ExportRefusesStandardOutputForADeckOfSeveralFiles) {
  const auto result =
      RunBouncecal("export --engine lammps --material " + Card().string() + " -o -");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("standard output"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists("-"));
}

// simulate drop --material simulates the card's law and ball (issue 18: it was refused), from
// the card's drop height unless one is given.
TEST(Cli, SimulateDropTakesTheLawBallAndHeightOfAMaterialCard) {
  const auto card = Card();
  const auto card_json = nlohmann::json::parse(ReadFileText(card));
  const auto drop = nlohmann::json::parse(
      StdoutOf("simulate drop --quiet --material " + card.string() + " --json -"));
  EXPECT_EQ(drop["contact_law"], card_json["contact_law"]);
  EXPECT_EQ(drop["ball"]["diameter_m"], card_json["ball"]["diameter_m"]);
  EXPECT_EQ(drop["drop_height_m"], 0.2);
  // A ball option beside the card would contradict it.
  const auto both =
      RunBouncecal("simulate drop --material " + card.string() + " --ball pingpong-40mm");
  EXPECT_EQ(both.exit_status, 3) << both.output;
}

// compare --material uses the card's drop height, ball and drag, and says where each came from
// (issue 28: it refused without --drop-height-m and ignored the card's drag).
TEST(Cli, CompareTakesTheHeightBallAndDragOfAMaterialCard) {
  const auto card = Card();  // steel-10mm from 0.2 m, no drag
  const std::string compare = "compare " + kSteelCsv + " --material ";
  const auto plain = RunBouncecal(compare + card.string());
  ASSERT_EQ(plain.exit_status, 0) << plain.output;
  EXPECT_NE(plain.output.find("h0 = 0.2 m (from the card)"), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find("(from the card)\n  drag off (from the card)"), std::string::npos)
      << plain.output;
  const auto json = nlohmann::json::parse(StdoutOf(compare + card.string() + " --json -"));
  EXPECT_EQ(json["drop_height_m"], 0.2);
  EXPECT_EQ(json["drop_height_source"], "card");
  EXPECT_EQ(json["drag"], false);
  EXPECT_EQ(json["drag_source"], "card");

  // A card fitted with drag simulates with drag unless --no-drag says otherwise; drag changes a
  // light ball's heights, so the RMS error moves.
  auto dragged = nlohmann::json::parse(ReadFileText(card));
  dragged["fit"]["drag"] = true;
  dragged["ball"] = {{"diameter_m", 0.04}, {"density_kg_per_m3", 80.6}, {"mass_kg", 0.0027}};
  const auto drag_card = ScratchPath("drag_card.json");
  std::ofstream(drag_card) << dragged.dump();
  const auto on = nlohmann::json::parse(StdoutOf(compare + drag_card.string() + " --json -"));
  EXPECT_EQ(on["drag"], true);
  EXPECT_EQ(on["drag_source"], "card");
  const auto off =
      nlohmann::json::parse(StdoutOf(compare + drag_card.string() + " --no-drag --json -"));
  EXPECT_EQ(off["drag"], false);
  EXPECT_EQ(off["drag_source"], "command line");
  EXPECT_NE(on["curves"][0]["rms_height_error_m"], off["curves"][0]["rms_height_error_m"]);
  const auto printed = RunBouncecal(compare + drag_card.string());
  EXPECT_NE(printed.output.find("drag on (from the card)"), std::string::npos) << printed.output;

  // A card fitted without a drop height cannot supply one: refused in one line naming the card.
  auto apex = nlohmann::json::parse(ReadFileText(card));
  apex["fit"]["drop_height_m"] = nullptr;
  apex["fit"]["release"] = "first-bounce-apex";
  const auto apex_card = ScratchPath("apex_card.json");
  std::ofstream(apex_card) << apex.dump();
  const auto refused = RunBouncecal(compare + apex_card.string());
  EXPECT_EQ(refused.exit_status, 3) << refused.output;
  EXPECT_NE(refused.output.find("apex_card.json was fitted from the first bounce's apex"),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("--drop-height-m"), std::string::npos) << refused.output;
  // Given, the height wins over the card's and is reported as the command line's.
  const auto given =
      nlohmann::json::parse(StdoutOf(compare + card.string() + " --drop-height-m 0.21 --json -"));
  EXPECT_EQ(given["drop_height_m"], 0.21);
  EXPECT_EQ(given["drop_height_source"], "command line");
}

// --contact-duration-s sets k_n so the simulated contact lasts that long (the law's closed form
// inverted; contact_stiffness_test.cc checks the formula).
TEST(Cli, ContactDurationSetsTheStiffnessOfTheSimulatedDrop) {
  const auto drop = nlohmann::json::parse(
      StdoutOf("simulate drop --quiet --ball tennis --gamma 0.3 --drop-height-m 1 "
               "--contact-duration-s 0.005 --integrator exact --json -"));
  // Gravity during the 5 ms contact lengthens it by about g / (omega v) = 9.81 / (628 x 4.4),
  // 0.35 %; 1 % allows that and fails a k_n off by 2 % or more.
  EXPECT_NEAR(drop["impacts"][0]["contact_duration_s"].get<double>(), 0.005, 0.005 * 0.01);
  // k_n = m (pi/2)^2 (1/sqrt(1.3) + 1/sqrt(0.7))^2 / t_c^2 for 57.7 g (docs/physics.md).
  EXPECT_NEAR(drop["contact_law"]["parameters"]["stiffness_n_per_m"].get<double>(), 2.4455e4, 1);
  // It replaces the stiffness: both together are refused.
  const auto both = RunBouncecal(
      "simulate drop --ball tennis --contact-duration-s 0.005 --stiffness-n-per-m 1e6");
  EXPECT_EQ(both.exit_status, 3) << both.output;
}

}  // namespace
}  // namespace bouncecal::testing
