#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

TEST(SimulateDropCli, WritesJsonAndTrajectoryOfThePaperDrop) {
  const auto json_path = ScratchPath("paper.json");
  const auto csv_path = ScratchPath("paper.csv");
  const auto result = RunBouncecal(
      "simulate drop --law walton-braun --gamma 0.5 --stiffness-n-per-m 1e7 --diameter-m 0.01 "
      "--density-kg-per-m3 "
      "7800 --drop-height-m 0.2 --json " +
      json_path.string() + " --trajectory " + csv_path.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("restitution"), std::string::npos);
  const auto json = nlohmann::json::parse(ReadFileText(json_path));
  ASSERT_GE(json.at("impacts").size(), 10u);
  const auto& first = json.at("impacts").at(0);
  for (const char* key : {"time_s", "restitution", "energy_loss", "contact_duration_s",
                          "max_overlap_m", "speed_in_mps", "speed_out_mps"}) {
    EXPECT_TRUE(first.at(key).is_number()) << key;
  }
  // The paper's law: e = sqrt((1 - 0.5)/(1 + 0.5)) = 0.577 up to the 50-step discretisation.
  EXPECT_NEAR(first.at("restitution").get<double>(), 0.5774, 2e-3);
  EXPECT_NEAR(first.at("time_s").get<double>(), std::sqrt(2 * 0.2 / 9.81), 1e-9);
  EXPECT_EQ(json.at("stop_reason"), "at_rest");
  EXPECT_TRUE(json.at("steps").is_number_integer());
  // The run time is printed, never stored: the JSON of a given run is reproducible (issue 7).
  EXPECT_FALSE(json.contains("cpu_s"));
  EXPECT_NE(result.output.find("cpu:"), std::string::npos) << result.output;
  const std::string csv = ReadFileText(csv_path);
  EXPECT_EQ(csv.rfind("time_s,height_m,velocity_mps\n", 0), 0u);
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 1000);
}

TEST(SimulateDropCli, NonsenseParametersExitWithStatusThreeAndOneLine) {
  for (const char* arguments :
       {"--gamma 1.5", "--stiffness-n-per-m -1e7", "--diameter-m 0", "--drop-height-m nan",
        "--law hertz --gamma 0.3", "--integrator leapfrog", "--time-step-s 1e-4"}) {
    const auto result = RunBouncecal(std::string("simulate drop ") + arguments);
    EXPECT_EQ(result.exit_status, 3) << arguments << ": " << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1)
        << arguments << ": " << result.output;
  }
}

TEST(SimulateDropCli, UnwritableJsonExitsWithStatusFour) {
  const auto result = RunBouncecal("simulate drop --quiet --json /nonexistent-dir/out.json");
  EXPECT_EQ(result.exit_status, 4) << result.output;
}

TEST(SimulateDropCli, HelpShowsAnExample) {
  const auto result = RunBouncecal("simulate drop --help");
  EXPECT_EQ(result.exit_status, 0);
  EXPECT_NE(result.output.find("Example"), std::string::npos);
  EXPECT_NE(result.output.find("--steps-per-contact"), std::string::npos);
}

}  // namespace
}  // namespace bouncecal::testing
