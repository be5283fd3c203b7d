#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

std::string Sample() { return (SourceDir() / "samples" / "steel_ball_h0.2m.wav").string(); }

std::filesystem::path Temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("bouncecal_calibrate_cli_" + name);
}

TEST(CalibrateCli, ShippedSampleGivesGammaNearTheFormulaWithJsonAndCard) {
  const auto json = Temp("fit.json"), card = Temp("card.json");
  const auto result = RunBouncecal("calibrate " + Sample() + " --json " + json.string() +
                                   " --card " + card.string() + " --bootstrap 8");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("gamma_n"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("analytic check"), std::string::npos) << result.output;
  std::ifstream in(json);
  const auto fit = nlohmann::json::parse(in);
  for (const char* key : {"law", "parameters", "confidence_interval", "analytic", "objective",
                          "residual", "evaluations", "stop_reason"}) {
    EXPECT_TRUE(fit.contains(key)) << key;
  }
  // The sample was synthesised with a constant eta = 0.58 (samples/README.md): gamma_n from the
  // formula is 0.408; the synthesiser's flights neglect the contact time (70 us of ~0.27 s) and
  // the fit's Verlet step adds ~5e-4, so 0.408 +- 5e-3.
  EXPECT_NEAR(fit["parameters"]["gamma_n"].get<double>(), 0.408, 5e-3);
  EXPECT_TRUE(fit["analytic"]["gamma_n"].is_number());
  std::ifstream card_in(card);
  EXPECT_EQ(nlohmann::json::parse(card_in)["format"], "bouncecal-material/1");
  std::filesystem::remove(json);
  std::filesystem::remove(card);
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The reproducible-builds convention: with SOURCE_DATE_EPOCH set, the card records that time and
// two runs give byte-identical cards (without it, created_utc is the wall clock).
TEST(CalibrateCli, SourceDateEpochMakesTheCardByteIdentical) {
  const auto first = Temp("epoch_1.json"), second = Temp("epoch_2.json");
  const std::string environment = "SOURCE_DATE_EPOCH=1700000000";
  const std::string arguments = "calibrate " + Sample() + " --bootstrap 0 --card ";
  ASSERT_EQ(RunBouncecal(arguments + first.string(), environment).exit_status, 0);
  ASSERT_EQ(RunBouncecal(arguments + second.string(), environment).exit_status, 0);
  const auto card = ReadFile(first);
  EXPECT_EQ(card, ReadFile(second));
  EXPECT_EQ(nlohmann::json::parse(card)["created_utc"], "2023-11-14T22:13:20Z");
  std::filesystem::remove(first);
  std::filesystem::remove(second);
}

TEST(CalibrateCli, MalformedSourceDateEpochIsAnOptionErrorBeforeTheFit) {
  const auto card = Temp("epoch_bad.json");
  for (const char* value : {"yesterday", "-5", "1e9", "99999999999999"}) {
    const auto result =
        RunBouncecal("calibrate " + Sample() + " --bootstrap 0 --card " + card.string(),
                     std::string("SOURCE_DATE_EPOCH=") + value);
    EXPECT_EQ(result.exit_status, 3) << value << ": " << result.output;
    EXPECT_NE(result.output.find("SOURCE_DATE_EPOCH"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(card)) << value;
  }
}

TEST(CalibrateCli, MissingRecordingExitsWithStatus2) {
  const auto result = RunBouncecal("calibrate /nonexistent/drop.wav");
  EXPECT_EQ(result.exit_status, 2) << result.output;
}

TEST(CalibrateCli, UnknownObjectiveOrLawExitsWithStatus3) {
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --objective energy").exit_status, 3);
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --law spring").exit_status, 3);
}

TEST(CalibrateCli, UnwritableCardExitsWithStatus4AndLeavesNothing) {
  const auto result =
      RunBouncecal("calibrate " + Sample() + " --bootstrap 0 --card /nonexistent/dir/card.json");
  EXPECT_EQ(result.exit_status, 4) << result.output;
}

TEST(SweepCli, PrintsTheAnalyticColumnForWaltonBraun) {
  const auto result = RunBouncecal("sweep --law walton-braun --gamma 0.1:0.9:0.2");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("0.6667"), std::string::npos) << result.output;  // 2*0.5/1.5
}

TEST(CompareCli, NeedsExactlyOneOfGammaOrMaterial) {
  EXPECT_EQ(RunBouncecal("compare " + Sample()).exit_status, 3);
  const auto result = RunBouncecal("compare " + Sample() + " --gamma 0.3,0.5");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("RMS"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
