#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <string>

#include "bouncecal/dem/packing.h"
#include "bouncecal/error.h"
#include "engine/pack_checkpoint_file.h"

namespace bouncecal::dem {
namespace {

// A small 3D pour that exercises every piece of state a checkpoint carries: 150 spheres in
// pour batches every 10 ms (pending particles and the random stream between batches), a mix of
// two sizes, friction and rotation (tangential springs, spins), a cylinder side and floor (wall
// springs). 0.12 s: the first batches reach the floor by about 0.05 s and pile up.
nlohmann::json SmallBatchPour() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "name": "checkpoint_pour",
    "particles": {"count": 150,
                  "diameter": {"distribution": "uniform", "min_m": 0.008, "max_m": 0.01},
                  "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "center_m": [0, 0, 0], "radius_m": 0.04, "height_m": 0.2},
    "insertion": {"type": "pour", "seed": 7, "batch_interval_s": 0.01,
                  "region": {"type": "cylinder", "center_m": [0, 0], "radius_m": 0.035,
                             "z_min_m": 0.01, "z_max_m": 0.05}},
    "material": {"contact_law": {"law": "walton-braun",
                                 "parameters": {"stiffness_n_per_m": 1e6, "gamma_n": 0.5}},
                 "tangential_stiffness_n_per_m": 1e6, "friction": 0.3},
    "physics": {"tangential": true, "rotation": true},
    "time_step_s": 1e-5,
    "duration_s": 0.12,
    "measurement": {"band_m": [0.005, 0.025], "history_interval_s": 0.005}
  })");
}

PackOptions Options(int threads) {
  PackOptions options;
  options.threads = threads;
  options.progress_every_steps = 700;  // blocks that do not line up with the batches
  return options;
}

// Runs until the first block boundary at or after `stop_step` and returns the checkpoint the
// interruption wrote.
std::string InterruptedAt(const Scene& scene, int threads, std::int64_t stop_step) {
  PackOptions options = Options(threads);
  std::string saved;
  std::int64_t blocks = 0;
  options.checkpoint = [&](const std::string& bytes, double) { saved = bytes; };
  options.progress = [&](const PackProgress& p) { blocks = p.steps; };
  options.stop_requested = [&] { return blocks >= stop_step; };
  const PackSummary summary = RunPacking(scene, options);
  EXPECT_EQ(summary.stop_reason, PackStopReason::kInterrupted) << summary.message;
  EXPECT_GE(summary.steps, stop_step);
  EXPECT_FALSE(saved.empty());
  return saved;
}

PackSummary ResumedFrom(const Scene& scene, int threads, const std::string& checkpoint) {
  PackOptions options = Options(threads);
  options.resume_checkpoint = checkpoint;
  options.resume_name = "test.bcpack";
  return RunPacking(scene, options);
}

TEST(PackCheckpoint, ResumedRunEndsInTheBitsOfTheUninterruptedRunOnOneAndTwoThreads) {
  const Scene scene = SceneFromJson(SmallBatchPour(), "checkpoint_pour.json");
  const PackSummary whole = RunPacking(scene, Options(1));
  ASSERT_EQ(whole.stop_reason, PackStopReason::kDuration) << whole.message;
  ASSERT_EQ(whole.particles, 150);
  // Stops between pour batches (pending particles left) and after the pile has formed.
  for (const std::int64_t stop_step : {2100, 9100}) {
    for (const int write_threads : {1, 2}) {
      for (const int resume_threads : {1, 2}) {
        SCOPED_TRACE(testing::Message() << "stop " << stop_step << ", written on " << write_threads
                                        << ", resumed on " << resume_threads);
        const auto checkpoint = InterruptedAt(scene, write_threads, stop_step);
        const PackSummary resumed = ResumedFrom(scene, resume_threads, checkpoint);
        ASSERT_EQ(resumed.stop_reason, PackStopReason::kDuration) << resumed.message;
        // Equality of the digest is equality of every bit of every position, velocity and spin.
        EXPECT_EQ(resumed.state_digest, whole.state_digest);
        EXPECT_EQ(resumed.steps, whole.steps);
        EXPECT_EQ(resumed.neighbor_rebuilds, whole.neighbor_rebuilds);
        EXPECT_EQ(resumed.particles, whole.particles);
        EXPECT_EQ(resumed.packing_density, whole.packing_density);
        ASSERT_EQ(resumed.history.size(), whole.history.size());
        EXPECT_EQ(resumed.history.back().kinetic_energy_j, whole.history.back().kinetic_energy_j);
      }
    }
  }
}

// A stop request is met at the step it arrives in, not at the end of the block (700 steps, or
// 500 between history samples): the step count at the stop is none of the block ends. Continued
// from that checkpoint, the run ends in the bits of the uninterrupted one: the whole kick the
// stopped block still owed is taken from the velocities it was owed on.
TEST(PackCheckpoint, StopInsideABlockIsMetWithinAStepAndResumesToTheUninterruptedBits) {
  const Scene scene = SceneFromJson(SmallBatchPour(), "checkpoint_pour.json");
  const PackSummary whole = RunPacking(scene, Options(1));
  ASSERT_EQ(whole.stop_reason, PackStopReason::kDuration) << whole.message;
  // The poll at which the request arrives: while the pour goes on and in the pile; neither is
  // at a block end (multiples of 500 and 700).
  for (const std::int64_t request : {2333, 9111}) {
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(testing::Message()
                   << "stop at poll " << request << ", " << threads << " thread(s)");
      PackOptions options = Options(threads);
      std::string saved;
      std::int64_t polls = 0;
      options.checkpoint = [&](const std::string& bytes, double) { saved = bytes; };
      options.stop_requested = [&] { return ++polls >= request; };
      const PackSummary stopped = RunPacking(scene, options);
      ASSERT_EQ(stopped.stop_reason, PackStopReason::kInterrupted) << stopped.message;
      // The engine asks once per step but a block's last, the run once after each block: one
      // poll per step, so the run ends with the step the request arrived in.
      EXPECT_EQ(stopped.steps, request);
      ASSERT_FALSE(saved.empty());
      const PackSummary resumed = ResumedFrom(scene, 3 - threads, saved);
      ASSERT_EQ(resumed.stop_reason, PackStopReason::kDuration) << resumed.message;
      EXPECT_EQ(resumed.state_digest, whole.state_digest);
      EXPECT_EQ(resumed.steps, whole.steps);
      EXPECT_EQ(resumed.neighbor_rebuilds, whole.neighbor_rebuilds);
      ASSERT_EQ(resumed.history.size(), whole.history.size());
      EXPECT_EQ(resumed.history.back().kinetic_energy_j, whole.history.back().kinetic_energy_j);
    }
  }
}

// A resumed run reports its own wall time and, in total_wall_s, that plus the wall time the
// checkpoint recorded of the run before it.
TEST(PackCheckpoint, ResumedRunCountsTheWallTimeOfTheRunBeforeItInItsTotal) {
  const Scene scene = SceneFromJson(SmallBatchPour(), "checkpoint_pour.json");
  PackOptions options = Options(1);
  std::string saved;
  std::int64_t polls = 0;
  options.checkpoint = [&](const std::string& bytes, double) { saved = bytes; };
  options.stop_requested = [&] { return ++polls >= 6000; };
  const PackSummary first = RunPacking(scene, options);
  ASSERT_EQ(first.stop_reason, PackStopReason::kInterrupted) << first.message;
  EXPECT_EQ(first.total_wall_s, first.wall_s);
  const PackSummary resumed = ResumedFrom(scene, 1, saved);
  // The checkpoint was written after first's steps and before its measures, on the clock that
  // timed it: more than nothing and no more than all of first.wall_s.
  EXPECT_GT(resumed.total_wall_s - resumed.wall_s, 0);
  EXPECT_LE(resumed.total_wall_s - resumed.wall_s, first.wall_s);
}

TEST(PackCheckpoint, PeriodicCheckpointsLeaveTheTrajectoryUnchanged) {
  const Scene scene = SceneFromJson(SmallBatchPour(), "checkpoint_pour.json");
  const PackSummary plain = RunPacking(scene, Options(1));
  PackOptions options = Options(1);
  options.checkpoint_every_s = 0.013;  // deliberately not a multiple of any block length
  int written = 0;
  std::string last;
  options.checkpoint = [&](const std::string& bytes, double) {
    ++written;
    last = bytes;
  };
  const PackSummary with = RunPacking(scene, options);
  EXPECT_EQ(with.state_digest, plain.state_digest);
  // 0.12 s at one per 0.013 s: 9 of them, at the first block boundary after each multiple.
  EXPECT_EQ(written, 9);
  // The last periodic checkpoint resumes to the same end too.
  EXPECT_EQ(ResumedFrom(scene, 2, last).state_digest, plain.state_digest);
}

// The message of the InputError that resuming from `bytes` raises, or "" when none is raised.
std::string RefusalOf(const Scene& scene, const std::string& bytes) {
  try {
    ResumedFrom(scene, 1, bytes);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(PackCheckpoint, DamagedTruncatedForeignOrOtherVersionCheckpointsAreRefusedNamingTheFile) {
  const Scene scene = SceneFromJson(SmallBatchPour(), "checkpoint_pour.json");
  const std::string good = InterruptedAt(scene, 1, 1400);
  ASSERT_EQ(RefusalOf(scene, good), "");

  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;  // one bit of one particle's state
  EXPECT_NE(RefusalOf(scene, flipped).find("test.bcpack: its checksum does not match"),
            std::string::npos)
      << RefusalOf(scene, flipped);

  for (const std::size_t keep : {good.size() - 1, good.size() / 3, std::size_t{20}}) {
    const std::string message = RefusalOf(scene, good.substr(0, keep));
    EXPECT_NE(message.find("test.bcpack: it ends early (truncated)"), std::string::npos)
        << keep << ": " << message;
  }
  EXPECT_NE(RefusalOf(scene, good.substr(0, 3)).find("is not a bouncecal pack checkpoint"),
            std::string::npos);
  EXPECT_NE(RefusalOf(scene, "{\"a\": 1}").find("is not a bouncecal pack checkpoint"),
            std::string::npos);

  // The version sits right after the 8-byte magic and the 4-byte byte-order mark.
  std::string other_version = good;
  const std::uint32_t next = scene::kPackCheckpointVersion + 1;
  std::memcpy(other_version.data() + 12, &next, sizeof(next));
  EXPECT_NE(RefusalOf(scene, other_version)
                .find("format version " + std::to_string(next) + ", this bouncecal reads version " +
                      std::to_string(scene::kPackCheckpointVersion)),
            std::string::npos)
      << RefusalOf(scene, other_version);

  // Another seed is another scene: the fingerprint of its set-up differs.
  nlohmann::json json = SmallBatchPour();
  json["insertion"]["seed"] = 8;
  const Scene other = SceneFromJson(json, "other.json");
  EXPECT_NE(RefusalOf(other, good).find("was written for another scene or other options"),
            std::string::npos)
      << RefusalOf(other, good);
  // So is another skin (it decides the pair list and the order of the force sums).
  PackOptions skin = Options(1);
  skin.skin_diameters = 0.2;
  skin.resume_checkpoint = good;
  EXPECT_THROW(RunPacking(scene, skin), InputError);
}

}  // namespace
}  // namespace bouncecal::dem
