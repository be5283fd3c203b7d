// Determinism (issue 7): the same input and seed give byte-identical output files, run after run,
// and the calibration gives the same answer on any number of threads (fit.h promises it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

class Determinism : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("bouncecal_determinism_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  // Runs `command`, in which every "{out}" stands for a fresh folder, and returns that folder.
  fs::path Run(const std::string& command, const std::string& name) {
    const fs::path out = folder_ / name;
    fs::create_directories(out);
    std::string expanded = command;
    for (auto at = expanded.find("{out}"); at != std::string::npos; at = expanded.find("{out}"))
      expanded.replace(at, 5, out.string());
    const auto result = RunBouncecal(expanded);
    EXPECT_EQ(result.exit_status, 0) << expanded << "\n" << result.output;
    return out;
  }

  fs::path folder_;
};

std::string Bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Result JSON states how long the run took (simulate: cpu_s; calibrate: fit_time_s,
// total_time_s). Those measured times are the only fields allowed to differ; they are removed
// at any depth before the byte comparison, so everything else must match exactly.
void RemoveTimings(nlohmann::json& json) {
  if (json.is_object()) {
    for (const char* key : {"cpu_s", "fit_time_s", "total_time_s"}) json.erase(key);
  }
  if (json.is_structured()) {
    for (auto& child : json) RemoveTimings(child);
  }
}

std::string Comparable(const fs::path& path) {
  if (path.extension() != ".json") return Bytes(path);
  auto json = nlohmann::json::parse(Bytes(path));
  RemoveTimings(json);
  return json.dump(2);
}

// Every file of the first run is in the second, byte for byte (JSON without its timings).
void ExpectSameFiles(const fs::path& first, const fs::path& second) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(first)) {
    ++files;
    const auto name = entry.path().filename();
    EXPECT_EQ(Comparable(entry.path()), Comparable(second / name)) << name << " differs";
  }
  EXPECT_GT(files, 0) << "the command wrote nothing to compare";
}

const std::string kSamples = SourceDir().string() + "/samples/";

TEST_F(Determinism, AnalyzeWritesTheSameJsonAndCsvEveryRun) {
  const std::string command = "analyze " + kSamples +
                              "steel_ball_h0.2m.wav --drop-height 0.2 --json {out}/a.json "
                              "--csv {out}/a.csv";
  ExpectSameFiles(Run(command, "first"), Run(command, "second"));
}

TEST_F(Determinism, SimulateDropWritesTheSameJsonAndTrajectoryEveryRun) {
  const std::string command =
      "simulate drop --quiet --law walton-braun --gamma 0.5 --stiffness 1e7 --diameter 0.01 "
      "--density 7800 --drop-height 0.2 --json {out}/drop.json --trajectory {out}/drop.csv";
  ExpectSameFiles(Run(command, "first"), Run(command, "second"));
}

TEST_F(Determinism, SynthWritesTheSameWavBytesForTheSameSeed) {
  const std::string command =
      "synth -o {out}/s.wav --truth {out}/s.csv --drop-height-m 0.3 --snr-db 30 --knock-s 0.1 "
      "--channels 2 --sample-rate-hz 44100 --format float --seed 11";
  const auto first = Run(command, "first");
  ExpectSameFiles(first, Run(command, "second"));
  // The seed is what varies the noise: another seed must give another file, or the check above
  // could pass on a generator that ignores it.
  const auto other =
      Run("synth -o {out}/s.wav --drop-height-m 0.3 --snr-db 30 --knock-s 0.1 --channels 2 "
          "--sample-rate-hz 44100 --format float --seed 12",
          "other_seed");
  EXPECT_NE(Bytes(first / "s.wav"), Bytes(other / "s.wav"));
}

TEST_F(Determinism, CalibrateGivesTheSameFitOnOneTwoAndThreeThreads) {
  const auto analysis =
      Run("analyze " + kSamples + "steel_ball_h0.2m.wav --json {out}/drop.json", "analysis");
  const std::string command = "calibrate " + (analysis / "drop.json").string() +
                              " --drop-height 0.2 --bootstrap 6 --seed 5 --json {out}/fit.json "
                              "--threads ";
  const auto one = Comparable(Run(command + "1", "one") / "fit.json");
  EXPECT_EQ(one, Comparable(Run(command + "2", "two") / "fit.json"));
  EXPECT_EQ(one, Comparable(Run(command + "3", "three") / "fit.json"));
  EXPECT_NE(one.find("confidence_interval"), std::string::npos) << one;
}

}  // namespace
}  // namespace bouncecal::testing
