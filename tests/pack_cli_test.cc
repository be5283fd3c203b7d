#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

// A 40-sphere pour for 0.05 s: enough to exercise every output, fast enough for CI.
std::filesystem::path WriteTinyScene(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const auto path = dir / "tiny.json";
  std::ofstream(path) << R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 40, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.03, "z_min_m": 0.0, "z_max_m": 0.05}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5, "duration_s": 0.05,
    "measurement": {"band_m": [0.005, 0.02]},
    "outputs": {"snapshot_interval_s": 0.025}
  })";
  return path;
}

TEST(PackCli, WritesSummaryJsonCsvAndDumps) {
  const auto dir = std::filesystem::temp_directory_path() / "bouncecal_pack_cli_test";
  std::filesystem::remove_all(dir);
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  const auto json_path = dir / "result.json";
  const auto result = RunBouncecal("pack " + scene.string() + " --threads 1 --out " + out.string() +
                                   " --json " + json_path.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  std::ifstream in(json_path);
  const auto json = nlohmann::json::parse(in);
  for (const char* key : {"packing_density", "mean_coordination", "particles", "steps", "wall_s",
                          "particle_steps_per_s"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["particles"], 40);
  EXPECT_EQ(json["steps"], 5000);
  for (const char* file :
       {"history.csv", "profile.csv", "coordination.csv", "particles.csv", "summary.json",
        "dump.000000000.lammpstrj", "dump.000005000.lammpstrj"}) {
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  }
  // Not a terminal: no progress bar in the captured output.
  EXPECT_EQ(result.output.find("ETA"), std::string::npos) << result.output;
  std::filesystem::remove_all(dir);
}

TEST(PackCli, MissingSceneIsAnInputFileError) {
  const auto result = RunBouncecal("pack /nonexistent/scene.json");
  EXPECT_EQ(result.exit_status, 2) << result.output;
}

// A bad value in the scene FILE is a malformed input file (README: status 2), like any other
// file; tests/bad_input_test.cc holds the whole catalogue.
TEST(PackCli, BadSceneValueIsAnInputErrorNamingTheKey) {
  const auto dir = std::filesystem::temp_directory_path() / "bouncecal_pack_cli_bad";
  std::filesystem::create_directories(dir);
  const auto path = dir / "bad.json";
  std::ofstream(path) << R"({"format": "bouncecal-scene/1", "time_step_s": -1})";
  const auto result = RunBouncecal("pack " + path.string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("bad.json"), std::string::npos) << result.output;
  std::filesystem::remove_all(dir);
}

// The shipped paper-004 scenes (2D disks: friction, rotation, van der Waals, local damping,
// velocity zeroed at the first contact; one and two species) for 5 ms (5000 steps) through the
// command line. dem's Paper004Scene tests run them for 0.05-0.1 s against the paper and are
// labelled `long`; this short run carries the same path (2D scene file -> insertion -> engine ->
// window measurement -> outputs) through the sanitized stage.
TEST(PackCli, ShippedPaper004ScenesRunBriefly) {
  for (const std::string name : {"paper004_disks_friction_vdw", "paper004_binary_c3"}) {
    const auto dir = std::filesystem::temp_directory_path() / ("bouncecal_pack_cli_" + name);
    std::filesystem::remove_all(dir);
    const auto json_path = dir / "result.json";
    const auto scene = SourceDir() / "samples/scenes" / (name + ".json");
    const auto result = RunBouncecal("pack " + scene.string() + " --duration 0.005 --out " +
                                     (dir / "out").string() + " --json " + json_path.string());
    ASSERT_EQ(result.exit_status, 0) << name << ": " << result.output;
    std::ifstream in(json_path);
    const auto json = nlohmann::json::parse(in);
    EXPECT_EQ(json["particles"], 240) << name;
    EXPECT_EQ(json["steps"], 5000) << name;  // 5 ms at the scenes' 1 us step
    // The window's area fraction: the random start fills 0.47 of the box and 5 ms of settling
    // (under local damping the disks fall less than a diameter) cannot halve that; no disk packing
    // exceeds the hexagonal pi / sqrt(12) = 0.9069.
    const double fraction = json["packing_density"];
    EXPECT_GT(fraction, 0.3) << name;
    EXPECT_LT(fraction, 0.9069) << name;
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace bouncecal::testing
