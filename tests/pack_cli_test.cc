#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
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

// The tiny scene launched downwards at 1e300 m/s: finite positions and velocities, but the
// kinetic energy (v^2) overflows to inf at once, and the run stops as unstable after one batch.
std::filesystem::path WriteRunawayScene(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const auto path = dir / "runaway.json";
  std::ofstream(path) << R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 40, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
    "insertion": {"type": "random", "initial_velocity_mps": [0, 0, -1e300],
                  "region": {"type": "cylinder", "radius_m": 0.03, "z_min_m": 0.0, "z_max_m": 0.05}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5, "duration_s": 0.05,
    "measurement": {"band_m": [0.005, 0.02]},
    "outputs": {"snapshot_interval_s": 0.025}
  })";
  return path;
}

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

TEST(PackCli, WritesSummaryJsonCsvAndDumps) {
  const auto dir = ScratchPath("test");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  const auto json_path = dir / "result.json";
  const auto result = RunBouncecal("pack " + scene.string() + " --threads 1 -o " + out.string() +
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
  // But the projection before the first step, for the scene's own particles and steps.
  EXPECT_NE(result.output.find("projected wall time: about"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("40 particles x 5000 steps on 1 thread"), std::string::npos)
      << result.output;
}

TEST(PackCli, MissingSceneIsAnInputFileError) {
  const auto result = RunBouncecal("pack /nonexistent/scene.json");
  EXPECT_EQ(result.exit_status, 2) << result.output;
}

// A bad value in the scene FILE is a malformed input file (README: status 2), like any other
// file; tests/bad_input_test.cc holds the whole catalogue.
TEST(PackCli, BadSceneValueIsAnInputErrorNamingTheKey) {
  const auto dir = ScratchPath("bad");
  std::filesystem::create_directories(dir);
  const auto path = dir / "bad.json";
  std::ofstream(path) << R"({"format": "bouncecal-scene/1", "time_step_s": -1})";
  const auto result = RunBouncecal("pack " + path.string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("bad.json"), std::string::npos) << result.output;
}

// The shipped paper-004 scenes (2D disks: friction, rotation, van der Waals, viscous or local
// damping, velocity zeroed at the first contact; one and two species) for 5 ms (5000 steps)
// through the command line. dem's Paper004Scene tests run them for 0.05-0.2 s against the paper
// and are
// labelled `long`; this short run carries the same path (2D scene file -> insertion -> engine ->
// window measurement -> outputs) through the sanitized stage.
TEST(PackCli, ShippedPaper004ScenesRunBriefly) {
  for (const std::string name : {"paper004_disks_friction_vdw",
                                 "paper004_disks_friction_vdw_literal", "paper004_binary_c3"}) {
    const auto dir = ScratchPath(name);
    const auto json_path = dir / "result.json";
    const auto scene = SourceDir() / "samples/scenes" / (name + ".json");
    const auto result = RunBouncecal("pack " + scene.string() + " --duration-s 0.005 -o " +
                                     (dir / "out").string() + " --json " + json_path.string());
    ASSERT_EQ(result.exit_status, 0) << name << ": " << result.output;
    std::ifstream in(json_path);
    const auto json = nlohmann::json::parse(in);
    EXPECT_EQ(json["particles"], 240) << name;
    EXPECT_EQ(json["steps"], 5000) << name;  // 5 ms at the scenes' 1 us step
    // The window's area fraction: the random start fills 0.47 of the box and 5 ms of settling
    // (a free fall of 0.12 mm, 1.2 diameters, at most) cannot halve that; no disk packing exceeds
    // the hexagonal pi / sqrt(12) = 0.9069.
    const double fraction = json["packing_density"];
    EXPECT_GT(fraction, 0.3) << name;
    EXPECT_LT(fraction, 0.9069) << name;
  }
}

// CLI::Range lets NaN through (every comparison with it is false); the run then used the scene's
// own duration without a word.
// dt 1e-5 s is within the normal contacts' limit (2.3e-5 s) but not the tangential spring's at
// k_t = 5e7 N/m (2 sqrt(m / (7 k_t)) = 7.6e-6 s): the run goes on (friction bounds the
// chatter) and says so on stderr and in summary.json. Ten times the step is refused (exit 3).
TEST(PackCli, StepBeyondTheTangentialLimitWarnsBeyondTheNormalLimitIsRefused) {
  const auto dir = ScratchPath("step_limits");
  std::filesystem::create_directories(dir);
  auto write = [&](const char* name, const char* step) {
    const auto path = dir / name;
    std::ofstream(path) << R"({
      "format": "bouncecal-scene/1",
      "particles": {"count": 40, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
      "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
      "insertion": {"type": "random", "region": {"type": "cylinder", "radius_m": 0.03,
                                                 "z_min_m": 0.0, "z_max_m": 0.05}},
      "material": {"contact_law": {"law": "walton-braun"}, "tangential_stiffness_n_per_m": 5e7},
      "time_step_s": )" << step
                        << R"(, "duration_s": 0.002,
      "measurement": {"band_m": [0.005, 0.02]}
    })";
    return path;
  };
  const auto json_path = dir / "result.json";
  const auto warned = RunBouncecal("pack " + write("warn.json", "1e-5").string() + " -o " +
                                   (dir / "out").string() + " --json " + json_path.string());
  ASSERT_EQ(warned.exit_status, 0) << warned.output;
  EXPECT_NE(warned.output.find("warning"), std::string::npos) << warned.output;
  EXPECT_NE(warned.output.find("tangential spring"), std::string::npos) << warned.output;
  std::ifstream in(json_path);
  const auto json = nlohmann::json::parse(in);
  // The tangential warning (the 2 ms run also ends before the spheres rest: a second one).
  bool tangential = false;
  for (const auto& warning : json["warnings"]) {
    tangential =
        tangential || warning.get<std::string>().find("tangential spring") != std::string::npos;
  }
  EXPECT_TRUE(tangential) << json["warnings"].dump();
  const auto refused = RunBouncecal("pack " + write("refuse.json", "1e-4").string() + " -o " +
                                    (dir / "out2").string());
  EXPECT_EQ(refused.exit_status, 3) << refused.output;
  EXPECT_NE(refused.output.find("normal contact"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out2"));
}

TEST(PackCli, NanDurationIsAnOptionErrorNamingTheOption) {
  const auto dir = ScratchPath("nan_duration");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  const auto result =
      RunBouncecal("pack " + scene.string() + " --duration-s nan -o " + out.string());
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("--duration-s"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out / "summary.json"));
}

// --precision single runs the pairs in float and says so; double is the default and says
// nothing; any other value is an option error naming the choices.
TEST(PackCli, PrecisionSingleSaysSoAndOtherValuesAreOptionErrors) {
  const auto dir = ScratchPath("precision");
  const auto scene = WriteTinyScene(dir);
  const auto single =
      RunBouncecal("pack " + scene.string() + " --precision single -o " + (dir / "s").string());
  ASSERT_EQ(single.exit_status, 0) << single.output;
  EXPECT_NE(single.output.find("single precision"), std::string::npos) << single.output;
  const auto plain = RunBouncecal("pack " + scene.string() + " -o " + (dir / "d").string());
  ASSERT_EQ(plain.exit_status, 0) << plain.output;
  EXPECT_EQ(plain.output.find("single precision"), std::string::npos) << plain.output;
  const auto half =
      RunBouncecal("pack " + scene.string() + " --precision half -o " + (dir / "h").string());
  EXPECT_EQ(half.exit_status, 3) << half.output;
  EXPECT_NE(half.output.find("--precision"), std::string::npos) << half.output;
  EXPECT_NE(half.output.find("single"), std::string::npos) << half.output;
}

// 1e-7 s at a 1e-5 s step ran 0 steps and reported the start state as the result. 0 itself is
// the documented way to measure the start state and stays allowed.
TEST(PackCli, DurationBelowOneTimeStepIsAnOptionErrorButZeroMeasuresTheStart) {
  const auto dir = ScratchPath("short_duration");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  const auto refused =
      RunBouncecal("pack " + scene.string() + " --duration-s 1e-7 -o " + out.string());
  EXPECT_EQ(refused.exit_status, 3) << refused.output;
  EXPECT_NE(refused.output.find("--duration-s"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("time_step_s"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << "refused before any output";

  const auto json_path = dir / "start.json";
  const auto start = RunBouncecal("pack " + scene.string() + " --duration-s 0 -o " + out.string() +
                                  " --json " + json_path.string());
  ASSERT_EQ(start.exit_status, 0) << start.output;
  std::ifstream in(json_path);
  const auto json = nlohmann::json::parse(in);
  EXPECT_EQ(json["steps"], 0);
  EXPECT_EQ(json["particles"], 40);
}

// A --json path in a missing folder was found only when the summary was written, after the
// whole simulation. Now it is refused first: no output folder, no CSV, no dump.
TEST(PackCli, JsonInMissingFolderIsRefusedBeforeSimulating) {
  const auto dir = ScratchPath("json_folder");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  const auto result =
      RunBouncecal("pack " + scene.string() + " --duration-s 0.001 -o " + out.string() +
                   " --json " + (dir / "missing" / "result.json").string());
  EXPECT_EQ(result.exit_status, 4) << result.output;
  EXPECT_NE(result.output.find("--json"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  // The folder this run created is removed again: nothing was simulated or written.
  EXPECT_FALSE(std::filesystem::exists(out)) << result.output;
}

// An existing output folder where no file can be made was found only at the first write, after
// the simulation. /proc is such a folder even for root (who ignores permission bits, so a
// chmod-ed folder would not do in a container running tests as root).
TEST(PackCli, OutputFolderWithoutWriteAccessIsRefusedBeforeSimulating) {
  if (!std::filesystem::is_directory("/proc")) GTEST_SKIP() << "no /proc on this system";
  const auto dir = ScratchPath("out_folder");
  const auto scene = WriteTinyScene(dir);
  const auto result = RunBouncecal("pack " + scene.string() + " --duration-s 0.001 -o /proc");
  EXPECT_EQ(result.exit_status, 4) << result.output;
  // The up-front check names the folder; the late failure named the first CSV it could not write.
  EXPECT_NE(result.output.find("output folder /proc"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("history.csv"), std::string::npos) << result.output;
}

// An unstable run wrote inf/-nan into history.csv and particles.csv and null into summary.json.
// Now: history up to its last finite row, no final-state tables (and none left over from an
// earlier run in the folder), and the JSON leaves out what is not a number.
TEST(PackCli, UnstableRunWritesNoNonFiniteNumberAndNoFinalState) {
  const auto dir = ScratchPath("unstable");
  const auto scene = WriteRunawayScene(dir);
  const auto out = dir / "out";
  std::filesystem::create_directories(out);
  for (const char* stale : {"particles.csv", "profile.csv", "coordination.csv"}) {
    std::ofstream(out / stale) << "from an earlier run\n";
  }
  const auto json_path = dir / "result.json";
  const auto result = RunBouncecal("pack " + scene.string() + " -o " + out.string() + " --json " +
                                   json_path.string());
  ASSERT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("unstable"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("runaway.json"), std::string::npos) << result.output;

  ASSERT_TRUE(std::filesystem::exists(out / "history.csv"));
  const std::string history = Lowercase(ReadFileText(out / "history.csv"));
  EXPECT_EQ(history.find("inf"), std::string::npos) << history;
  EXPECT_EQ(history.find("nan"), std::string::npos) << history;
  for (const char* file : {"particles.csv", "profile.csv", "coordination.csv"}) {
    EXPECT_FALSE(std::filesystem::exists(out / file)) << file;
  }
  for (const auto& path : {out / "summary.json", json_path}) {
    std::ifstream in(path);
    const auto json = nlohmann::json::parse(in);
    EXPECT_EQ(json["stop_reason"], "unstable") << path;
    // What was not measured is null (docs/json.md), never a number standing in for it.
    EXPECT_TRUE(json.at("kinetic_energy_j").is_null()) << path;  // the blown-up state's: not kept
    EXPECT_TRUE(json.at("packing_density").is_null()) << path;   // never measured
    EXPECT_TRUE(json.at("mean_coordination").is_null()) << path;
    EXPECT_TRUE(json.at("time_step_s").is_number()) << path;
  }
}

// 40 frictionless spheres dropped into the tiny scene's cylinder for 0.5 s at `step`. At 2e-5 s
// (0.86 of the 2.33e-5 s limit of one contact) the pack boils: once the spheres have landed
// (0.07 s) their kinetic energy never falls again, 0.02-0.05 J to the end, under the energy
// budget's 2x of what the fall brought in; at 1e-5 s the same spheres come to rest (4e-6 J at
// the end, 2e-4 of the peak). Each run takes ~0.15 s of wall time.
std::filesystem::path WriteBoilingScene(const std::filesystem::path& dir, const char* name,
                                        const char* step) {
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 40, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.03, "z_min_m": 0.0, "z_max_m": 0.05}},
    "physics": {"tangential": false, "rotation": false},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": )" << step
                      << R"(, "duration_s": 0.5,
    "measurement": {"band_m": [0.005, 0.02]}
  })";
  return path;
}

// A pack whose step heats it as fast as its damping cools it ran to its duration and exited 0,
// its "packing" a boiling state. README's table: status 3 (a well-formed scene that asks for
// the impossible), every output written, and summary.json says why. The same scene at half the
// step settles and exits 0, so the status is the step's doing, not the check's.
TEST(PackCli, BoilingPackExitsWithStatus3AndItsSummarySaysWhy) {
  const auto dir = ScratchPath("boiling");
  const auto out = dir / "out";
  const auto json_path = dir / "result.json";
  const auto boiled =
      RunBouncecal("pack " + WriteBoilingScene(dir, "boiling.json", "2e-5").string() + " -o " +
                   out.string() + " --json " + json_path.string());
  ASSERT_EQ(boiled.exit_status, 3) << boiled.output;
  // One error line naming the scene file, what happened and what to do.
  EXPECT_NE(boiled.output.find("error: " + (dir / "boiling.json").string() +
                               ": the particles never came to rest"),
            std::string::npos)
      << boiled.output;
  EXPECT_NE(boiled.output.find("Use a smaller time_step_s"), std::string::npos) << boiled.output;
  for (const char* file : {"history.csv", "profile.csv", "coordination.csv", "particles.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  }
  for (const auto& path : {out / "summary.json", json_path}) {
    std::ifstream in(path);
    const auto json = nlohmann::json::parse(in);
    EXPECT_TRUE(json["boiling"].get<bool>()) << path;
    EXPECT_EQ(json["stop_reason"], "duration") << path;  // it did run to its end
    EXPECT_EQ(json["steps"], 25000) << path;
    const std::string message = json["message"];
    EXPECT_NE(message.find("never came to rest"), std::string::npos) << path << ": " << message;
    EXPECT_NE(message.find("step of 2e-05 s"), std::string::npos) << path << ": " << message;
    bool not_at_rest = false;
    for (const auto& warning : json["warnings"]) {
      not_at_rest = not_at_rest ||
                    warning.get<std::string>().find("have not come to rest") != std::string::npos;
    }
    EXPECT_TRUE(not_at_rest) << path << ": " << json["warnings"].dump();
  }

  const auto settled =
      RunBouncecal("pack " + WriteBoilingScene(dir, "settling.json", "1e-5").string() + " -o " +
                   (dir / "settled").string());
  ASSERT_EQ(settled.exit_status, 0) << settled.output;
  std::ifstream in(dir / "settled" / "summary.json");
  const auto json = nlohmann::json::parse(in);
  EXPECT_FALSE(json["boiling"].get<bool>());
  EXPECT_EQ(json["message"], "ran 50000 steps to t = 0.5 s");
}

// Dumps and plots of an earlier, longer run stayed beside the new run's and were mixed with
// them. A rerun removes this command's own file names and nothing else.
TEST(PackCli, RerunRemovesOnlyTheEarlierRunsOwnOutputs) {
  const auto dir = ScratchPath("stale");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  std::filesystem::create_directories(out / "keep_folder");
  for (const char* stale : {"dump.000099999.lammpstrj", "profile.png", "history.png", "plots.gp"}) {
    std::ofstream(out / stale) << "from an earlier run\n";
  }
  for (const char* other : {"notes.txt", "dump.final.lammpstrj", "history.csv.bak"}) {
    std::ofstream(out / other) << "the user's own\n";
  }
  const auto result =
      RunBouncecal("pack " + scene.string() + " --duration-s 0.001 -o " + out.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  for (const char* stale : {"dump.000099999.lammpstrj", "profile.png", "history.png", "plots.gp"}) {
    EXPECT_FALSE(std::filesystem::exists(out / stale)) << stale;
  }
  for (const char* other :
       {"notes.txt", "dump.final.lammpstrj", "history.csv.bak", "keep_folder"}) {
    EXPECT_TRUE(std::filesystem::exists(out / other)) << other;
  }
  // This run's own: the dumps at t = 0 and at the end (step 100).
  EXPECT_TRUE(std::filesystem::exists(out / "dump.000000000.lammpstrj"));
  EXPECT_TRUE(std::filesystem::exists(out / "dump.000000100.lammpstrj"));
  EXPECT_TRUE(std::filesystem::exists(out / "summary.json"));
}

// A run refused at set-up (here: a time step beyond the normal contacts' limit, found only once
// the particles are placed) removed the earlier run's outputs before it was refused, leaving
// the folder empty. Nothing goes until every check has passed.
TEST(PackCli, RunRefusedAtSetUpLeavesTheEarlierRunsOutputs) {
  const auto dir = ScratchPath("refused_keeps");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  ASSERT_EQ(RunBouncecal("pack " + scene.string() + " --duration-s 0.001 --output " + out.string())
                .exit_status,
            0);
  const std::string summary = ReadFileText(out / "summary.json");
  std::string text = ReadFileText(scene);
  const std::string fine = "\"time_step_s\": 1e-5";
  text.replace(text.find(fine), fine.size(), "\"time_step_s\": 1e-3");
  std::ofstream(dir / "coarse.json") << text;
  const auto refused = RunBouncecal("pack " + (dir / "coarse.json").string() +
                                    " --duration-s 0.01 --output " + out.string());
  ASSERT_EQ(refused.exit_status, 3) << refused.output;
  EXPECT_NE(refused.output.find("normal contact"), std::string::npos) << refused.output;
  EXPECT_EQ(ReadFileText(out / "summary.json"), summary);
  for (const char* file :
       {"history.csv", "particles.csv", "dump.000000000.lammpstrj", "dump.000000100.lammpstrj"}) {
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  }
}

// A pid that no process has any more: a child that has exited and been reaped.
pid_t DeadPid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  int status = 0;
  waitpid(pid, &status, 0);
  return pid;
}

// A run killed while writing (SIGKILL, a second SIGINT) leaves AtomicFile's temporary
// "<name>.tmp.<pid>". The next run in the folder removes those of processes that are gone, and
// only of this command's own file names: a live process may be writing the others right now.
TEST(PackCli, NextRunRemovesTheTemporariesOfAKilledRunOnly) {
  const auto dir = ScratchPath("stale_tmp");
  const auto scene = WriteTinyScene(dir);
  const auto out = dir / "out";
  std::filesystem::create_directories(out);
  const std::string dead = std::to_string(DeadPid());
  const std::string alive = std::to_string(getpid());
  const std::vector<std::string> stale = {"summary.json.tmp." + dead,
                                          "checkpoint.bcpack.tmp." + dead,
                                          "dump.000000300.lammpstrj.tmp." + dead};
  const std::vector<std::string> kept = {"history.csv.tmp." + alive, "notes.txt.tmp." + dead,
                                         "summary.json.tmp.x" + dead};
  for (const auto& name : stale) std::ofstream(out / name) << "half";
  for (const auto& name : kept) std::ofstream(out / name) << "half";
  const auto result =
      RunBouncecal("pack " + scene.string() + " --duration-s 0.001 --output " + out.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  for (const auto& name : stale) EXPECT_FALSE(std::filesystem::exists(out / name)) << name;
  for (const auto& name : kept) EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
}

// `pack --template NAME` writes a commented scene that loads and whose set-up draws no warning
// (the time step, the region); run for 0 s, which measures the start state after every check.
TEST(PackCli, TemplatesLoadAndRunWithoutAWarning) {
  for (const std::string name : {"3d-cylinder", "2d-box"}) {
    const auto dir = ScratchPath("template_" + name);
    std::filesystem::create_directories(dir);
    const auto written = RunBouncecal("pack --template " + name);
    ASSERT_EQ(written.exit_status, 0) << written.output;
    const auto scene = nlohmann::json::parse(written.output);  // stdout holds the JSON alone
    EXPECT_TRUE(scene.contains("_comment")) << name;
    std::ofstream(dir / "scene.json") << written.output;
    const auto run = RunBouncecal("pack " + (dir / "scene.json").string() + " --duration-s 0 -o " +
                                  (dir / "out").string());
    EXPECT_EQ(run.exit_status, 0) << name << ": " << run.output;
    EXPECT_EQ(Lowercase(run.output).find("warning"), std::string::npos) << name << run.output;
  }
  const auto unknown = RunBouncecal("pack --template 4d-hypercube");
  EXPECT_EQ(unknown.exit_status, 3) << unknown.output;
  EXPECT_NE(unknown.output.find("3d-cylinder"), std::string::npos) << unknown.output;
  const auto nothing = RunBouncecal("pack");
  EXPECT_EQ(nothing.exit_status, 3) << nothing.output;
  EXPECT_NE(nothing.output.find("--template"), std::string::npos) << nothing.output;
}

// The paper 000 scene keeps the paper's 10 us step, 0.65 of the tangential limit: it says why
// (time_step_reason), so every run prints that as a note, not as a warning about itself.
TEST(PackCli, ShippedPaper000SceneExplainsItsStepInsteadOfWarning) {
  const auto dir = ScratchPath("paper000_note");
  const auto scene = SourceDir() / "samples/scenes/paper000_cylinder_pour.json";
  const auto run = RunBouncecal("pack " + scene.string() + " --duration-s 0 -o " + dir.string());
  ASSERT_EQ(run.exit_status, 0) << run.output;
  EXPECT_EQ(Lowercase(run.output).find("warning"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("bouncecal: note: "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("the paper's own 10 us"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace bouncecal::testing
