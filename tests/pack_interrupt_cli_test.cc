// `bouncecal pack` stopped by a signal and resumed from its checkpoint (docs/scenes.md,
// "Checkpoints and interruption").
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

// 60 spheres poured in three batches (pending particles, the random stream), with friction and
// rotation, for 0.3 s: long enough (30 000 steps, about a second) to be stopped part-way.
std::filesystem::path WritePourScene(const std::filesystem::path& dir) {
  const auto path = dir / "pour.json";
  std::ofstream(path) << R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 60, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.2},
    "insertion": {"type": "pour", "batch_interval_s": 0.04, "seed": 3,
                  "region": {"type": "cylinder", "radius_m": 0.028, "z_min_m": 0.02,
                             "z_max_m": 0.04}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "physics": {"tangential": true, "rotation": true},
    "time_step_s": 1e-5, "duration_s": 0.3,
    "measurement": {"band_m": [0.005, 0.02]},
    "outputs": {"snapshot_interval_s": 0.1}
  })";
  return path;
}

// Starts bouncecal with `arguments` (output to `log`), and returns its pid.
pid_t Spawn(const std::vector<std::string>& arguments, const std::filesystem::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string program = BOUNCECAL_EXECUTABLE;
    argv.push_back(program.data());
    std::vector<std::string> copy = arguments;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::FILE* out = std::freopen(log.c_str(), "w", stdout);
    if (out == nullptr || dup2(fileno(stdout), STDERR_FILENO) < 0) _exit(127);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// The exit status, or -signal when a signal ended it.
int Wait(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// The issue's acceptance test: SIGTERM at a random moment, resume, and the uninterrupted run's
// digest (every bit of every final position, velocity and spin), on one and two threads. The
// moment is random on purpose (a fixed one would always hit the same kind of block boundary);
// it is printed, so a failure can be replayed.
TEST(PackInterrupt, SigtermAtARandomMomentThenResumeGivesTheUninterruptedDigest) {
  const auto dir = ScratchSubfolder("interrupt");
  const auto scene = WritePourScene(dir);
  const auto started = std::chrono::steady_clock::now();
  const auto whole =
      RunBouncecal("pack " + scene.string() + " --output " + (dir / "whole").string());
  const auto whole_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::steady_clock::now() - started)
                            .count();
  ASSERT_EQ(whole.exit_status, 0) << whole.output;
  const std::string digest = ReadJsonFile(dir / "whole" / "summary.json")["state_digest"];
  std::random_device device;
  std::mt19937 random(device());
  // The moment is drawn within this host's own run time (a fast CI machine ran the whole pour
  // in 50 ms, so a fixed 0-500 ms range mostly signalled a finished run).
  const int latest_ms = static_cast<int>(std::max<long long>(1, whole_ms));
  for (const int threads : {1, 2}) {
    const auto out = dir / ("stopped" + std::to_string(threads));
    const auto log = dir / ("stopped" + std::to_string(threads) + ".log");
    // A run that ends before the signal arrives proves nothing: try again sooner.
    int status = 0;
    int delay_ms = std::uniform_int_distribution<int>(0, latest_ms)(random);
    for (int attempt = 0; attempt < 8; ++attempt, delay_ms /= 2) {
      std::filesystem::remove_all(out);
      const pid_t pid = Spawn(
          {"pack", scene.string(), "--threads", std::to_string(threads), "--output", out.string()},
          log);
      // The handler is installed before the output folder is made: a signal before that would
      // meet the default action (killed, no checkpoint), which is not what is tested here.
      for (int wait = 0; wait < 2000 && !std::filesystem::exists(out); ++wait) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
      kill(pid, SIGTERM);
      status = Wait(pid);
      // Too late: the run had finished (exit 0), or had written its whole summary and given the
      // signal back its default action on the way out (-SIGTERM; its buffered stdout is lost).
      const bool finished_before_the_signal =
          status == 0 || (status == -SIGTERM && std::filesystem::exists(out / "summary.json") &&
                          ReadJsonFile(out / "summary.json")["stop_reason"] == "duration");
      if (!finished_before_the_signal) break;
    }
    SCOPED_TRACE(::testing::Message()
                 << threads << " thread(s), SIGTERM after " << delay_ms << " ms");
    const std::string output = ReadFileText(log);
    ASSERT_EQ(status, 6) << output;
    // One line says what happened and how to go on.
    EXPECT_NE(output.find("stopped (SIGTERM)"), std::string::npos) << output;
    EXPECT_NE(output.find("--resume"), std::string::npos) << output;
    const auto stopped = ReadJsonFile(out / "summary.json");
    EXPECT_EQ(stopped["stop_reason"], "interrupted");
    EXPECT_LT(stopped["simulated_s"].get<double>(), 0.3);
    EXPECT_TRUE(stopped.contains("packing_density"));  // what was measured so far

    const auto resumed = RunBouncecal("pack " + scene.string() + " --threads " +
                                      std::to_string(3 - threads) + " --output " + out.string() +
                                      " --resume " + (out / "checkpoint.bcpack").string());
    ASSERT_EQ(resumed.exit_status, 0) << resumed.output;
    const auto end = ReadJsonFile(out / "summary.json");
    EXPECT_EQ(end["stop_reason"], "duration");
    EXPECT_EQ(end["state_digest"], digest);
    EXPECT_EQ(end["steps"], 30000);
    // wall_s times the resumed run alone; total_wall_s adds the stopped run's time up to its
    // checkpoint, which its own wall_s (taken after the checkpoint) bounds.
    const double own = end["wall_s"];
    const double earlier = end["total_wall_s"].get<double>() - own;
    EXPECT_GT(earlier, 0);
    EXPECT_LE(earlier, stopped["wall_s"].get<double>());
    // The resumed run's history and dumps are the whole run's.
    EXPECT_EQ(ReadFileText(out / "history.csv"), ReadFileText(dir / "whole" / "history.csv"));
    EXPECT_EQ(ReadFileText(out / "dump.000030000.lammpstrj"),
              ReadFileText(dir / "whole" / "dump.000030000.lammpstrj"));
  }
}

TEST(PackInterrupt, SecondSignalExitsAtOnceLeavingOnlyWholeFiles) {
  const auto dir = ScratchSubfolder("interrupt_twice");
  const auto scene = WritePourScene(dir);
  const auto out = dir / "out";
  const pid_t pid = Spawn({"pack", scene.string(), "--output", out.string(), "--duration-s", "100"},
                          dir / "log.txt");
  // The handler is installed before the output folder is made; a signal before that would meet
  // the default action (killed, status -2), which is not what is tested here. A slow start (the
  // sanitizers) must not decide the outcome, so the test waits for the folder, up to 10 s.
  for (int wait = 0; wait < 2000 && !std::filesystem::exists(out); ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kill(pid, SIGINT);
  kill(pid, SIGINT);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(Wait(pid), 6) << ReadFileText(dir / "log.txt");
  // "At once": well before the 100 s run would end, and before a block of steps would.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  // Whatever was written is whole: every file under its own name parses or reads fully; a
  // temporary (*.tmp.<pid>) may be left, and the next run removes it (PackCli test below).
  if (std::filesystem::exists(out / "summary.json")) {
    EXPECT_NO_THROW(ReadJsonFile(out / "summary.json"));
  }
}

TEST(PackInterrupt, PeriodicCheckpointResumesToTheSameDigestAndDoesNotChangeTheRun) {
  const auto dir = ScratchSubfolder("periodic");
  const auto scene = WritePourScene(dir);
  const auto plain = RunBouncecal("pack " + scene.string() + " --duration-s 0.12 --output " +
                                  (dir / "plain").string());
  ASSERT_EQ(plain.exit_status, 0) << plain.output;
  const auto with = RunBouncecal("pack " + scene.string() +
                                 " --duration-s 0.12 --checkpoint-every-s 0.05 --output " +
                                 (dir / "with").string());
  ASSERT_EQ(with.exit_status, 0) << with.output;
  const std::string digest = ReadJsonFile(dir / "plain" / "summary.json")["state_digest"];
  EXPECT_EQ(ReadJsonFile(dir / "with" / "summary.json")["state_digest"], digest);
  // The last checkpoint (t = 0.1 s) continues to the same end.
  const auto resumed = RunBouncecal("pack " + scene.string() + " --duration-s 0.12 --output " +
                                    (dir / "with").string() + " --resume " +
                                    (dir / "with" / "checkpoint.bcpack").string());
  ASSERT_EQ(resumed.exit_status, 0) << resumed.output;
  EXPECT_EQ(ReadJsonFile(dir / "with" / "summary.json")["state_digest"], digest);
}

TEST(PackInterrupt, DamagedOrForeignCheckpointIsRefusedInOneLineNamingTheFile) {
  const auto dir = ScratchSubfolder("bad_checkpoint");
  const auto scene = WritePourScene(dir);
  ASSERT_EQ(RunBouncecal("pack " + scene.string() +
                         " --duration-s 0.05 --checkpoint-every-s 0.02 --output " +
                         (dir / "out").string())
                .exit_status,
            0);
  const std::string good = ReadFileText(dir / "out" / "checkpoint.bcpack");
  ASSERT_GT(good.size(), 1000u);
  auto refused = [&](const std::string& name, const std::string& bytes,
                     const std::string& problem) {
    const auto path = dir / name;
    std::ofstream(path, std::ios::binary) << bytes;
    const auto result = RunBouncecal("pack " + scene.string() + " --duration-s 0.05 --output " +
                                     (dir / "resumed").string() + " --resume " + path.string());
    EXPECT_EQ(result.exit_status, 2) << result.output;
    EXPECT_NE(result.output.find(path.string() + ": " + problem), std::string::npos)
        << result.output;
    // One line, and nothing was run or written.
    EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "resumed" / "summary.json"));
  };
  refused("cut.bcpack", good.substr(0, good.size() / 2), "it ends early (truncated)");
  std::string flipped = good;
  flipped[good.size() - 100] ^= 1;
  refused("flipped.bcpack", flipped, "its checksum does not match");
  refused("text.bcpack", "not a checkpoint\n", "is not a bouncecal pack checkpoint");
  // The same scene with another seed is another scene.
  std::string other = ReadFileText(scene);
  other.replace(other.find("\"seed\": 3"), 9, "\"seed\": 4");
  std::ofstream(dir / "other.json") << other;
  const auto foreign = RunBouncecal("pack " + (dir / "other.json").string() +
                                    " --duration-s 0.05 --output " + (dir / "resumed").string() +
                                    " --resume " + (dir / "out" / "checkpoint.bcpack").string());
  EXPECT_EQ(foreign.exit_status, 2) << foreign.output;
  EXPECT_NE(foreign.output.find("was written for another scene or other options"),
            std::string::npos)
      << foreign.output;
}

}  // namespace
}  // namespace bouncecal::testing
