// Runs the exported single-drop deck in the real engines (Debian lammps and liggghts) and checks
// that the restitution they produce is the material card's. Skips, with a message, when an
// engine is not installed; scripts/install_deps.sh installs both, so CI runs them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "bouncecal/dem/laws/walton_braun.h"
#include "bouncecal/export/trajectory_bounces.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "external_engine.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

constexpr double kGammaN = 0.5;
constexpr double kStiffnessNPerM = 1e7;
constexpr double kDiameterM = 0.01;
constexpr double kDensity = 7800;
constexpr double kGravity = 9.81;

// A fresh folder per test and process, removed afterwards unless the test failed.
class ExportedDeck : public ::testing::Test {
 protected:
  void SetUp() override {
    // The paper's material (docs/physics.md section 3): 1 cm steel ball, k = 1e7 N/m,
    // gamma_n = 0.5.
    std::ofstream(folder_ / "card.json") << R"({
      "format": "bouncecal-material/1",
      "contact_law": {"law": "walton-braun",
                      "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
      "ball": {"diameter_m": 0.01, "density_kg_per_m3": 7800, "mass_kg": null},
      "implied": {"restitution": 0.5773502691896257, "energy_loss": 0.6666666666666667}
    })";
  }

  // Exports the card for `engine`, runs the deck with `executable` and checks every resolved
  // bounce against the card.
  void ExportRunAndCheck(const std::string& engine, const std::string& executable) {
    const fs::path deck = folder_ / ("deck-" + engine);
    const auto exported =
        RunBouncecal("export --material " + (folder_ / "card.json").string() + " --engine " +
                     engine + " -o " + deck.string() + " --bounces 6");
    ASSERT_EQ(exported.exit_status, 0) << exported.output;
    const std::string run_line = "cd " + deck.string() + " && " + executable;
    ASSERT_NE(exported.output.find(run_line), std::string::npos)
        << "the command's output must name the command that runs the deck:\n"
        << exported.output;

    const int status = std::system(("cd " + deck.string() + " && " + executable +
                                    " -in in.drop -log log." + engine + " > run.out 2>&1")
                                       .c_str());
    ASSERT_EQ(status, 0) << executable << " failed; end of its output:\n" << Tail(deck / "run.out");

    const auto samples = calibrate::ReadTrajectory(deck / "trajectory.txt");
    const auto found = calibrate::FindTrajectoryBounces(samples, {0.5 * kDiameterM, 0, kGravity});

    const double mass = kDensity * std::numbers::pi * std::pow(kDiameterM, 3) / 6;
    const dem::WaltonBraun law({.stiffness_n_per_m = kStiffnessNPerM, .gamma_n = kGammaN});
    const double card_e = 0.5773502691896257;  // the card's implied restitution
    const double closed_form_e = std::sqrt((1 - kGammaN) / (1 + kGammaN));
    ASSERT_NEAR(card_e, closed_form_e, 1e-12) << "the test card must state its own law's e";
    const double contact_s = *law.ClosedFormContactDuration(mass, 0.5 * kDiameterM, 1.0);

    // 1 % is achievable and meaningful: the deck's step is t_c/553, which bounds the error of the
    // damping-force jumps at touch and separation to 2|ln e| dt/t_c = 0.2 %; the ballistic
    // extrapolation of the output is exact; gravity during the contact (which the closed form
    // leaves out) shifts e by about g t_c / v, kept below 0.3 % by only checking bounces whose
    // impact speed v >= g t_c / 0.003 (about 0.23 m/s: the first 5). The mistakes the check must
    // catch are larger: the pair coefficients on the wall (m_eff = m/2 convention) give e = 0.454
    // (-21 %), the card's k instead of the matched k' gives 0.607 (+5 %).
    const double min_speed = kGravity * contact_s / 0.003;
    int checked = 0;
    for (size_t k = 0; k < found.bounces.size(); ++k) {
      const auto& bounce = found.bounces[k];
      if (bounce.impact_speed_mps < min_speed) continue;
      ++checked;
      EXPECT_NEAR(bounce.restitution / card_e, 1.0, 0.01)
          << engine << " bounce " << k + 1 << " at " << bounce.impact_speed_mps << " m/s";
      // Equal contact duration is the other half of the mapping: the same 1 % (the engine
      // detects touch and separation to within one step, 0.2 % of t_c).
      EXPECT_NEAR((bounce.contact_end_s - bounce.contact_start_s) / contact_s, 1.0, 0.01)
          << engine << " bounce " << k + 1;
    }
    EXPECT_GE(checked, 4) << "too few fast bounces in the trajectory: " << found.bounces.size()
                          << " found";
    EXPECT_EQ(found.unresolved_contacts, 0);

    // The user's route to the same verdict: export-check reads deck.json and the trajectory.
    const auto verdict = RunBouncecal("export-check " + deck.string());
    EXPECT_EQ(verdict.exit_status, 0) << verdict.output;
    EXPECT_NE(verdict.output.find("PASSED"), std::string::npos) << verdict.output;

    // A deck that promised 5 % more restitution than the engine gave (the size of the card-k
    // mistake above) must fail the check with its own exit status, so scripts can stop on it.
    const fs::path record_path = deck / "deck.json";
    auto record = nlohmann::json::parse(std::ifstream(record_path));
    record["expected"]["restitution"] = record["expected"]["restitution"].get<double>() * 1.05;
    std::ofstream(record_path) << record.dump(2);
    const auto tampered = RunBouncecal("export-check " + deck.string());
    EXPECT_EQ(tampered.exit_status, 5) << tampered.output;
    EXPECT_NE(tampered.output.find("FAILED"), std::string::npos) << tampered.output;
  }

  const ScratchFolder folder_;
};

TEST_F(ExportedDeck, LammpsReproducesTheCardsRestitutionWithinOnePercent) {
  if (!OnPath("lmp")) {
    GTEST_SKIP() << "LAMMPS (lmp, Debian package lammps) is not installed; "
                    "scripts/install_deps.sh installs it";
  }
  ExportRunAndCheck("lammps", "lmp");
}

TEST_F(ExportedDeck, LiggghtsReproducesTheCardsRestitutionWithinOnePercent) {
  if (!OnPath("liggghts")) {
    GTEST_SKIP() << "LIGGGHTS (liggghts, Debian package liggghts) is not installed; "
                    "scripts/install_deps.sh installs it";
  }
  ExportRunAndCheck("liggghts", "liggghts");
}

TEST_F(ExportedDeck, LammpsRunsTheLinearDashpotCardExactly) {
  if (!OnPath("lmp")) {
    GTEST_SKIP() << "LAMMPS (lmp, Debian package lammps) is not installed; "
                    "scripts/install_deps.sh installs it";
  }
  // The engines' own law: no mapping, so the engine must give the card's e = exp(-pi zeta /
  // sqrt(1 - zeta^2)) = 0.3723 within export-check's allowance (step bound + g t_c / v); a 0.5 %
  // step bound halves the run and still leaves the check meaningful.
  std::ofstream(folder_ / "linear.json") << R"({
      "format": "bouncecal-material/1",
      "contact_law": {"law": "linear-dashpot",
                      "parameters": {"stiffness_n_per_m": 2e7, "damping_ratio": 0.3}},
      "ball": {"diameter_m": 0.01, "density_kg_per_m3": 7800}
    })";
  const fs::path deck = folder_ / "deck-linear";
  const auto exported =
      RunBouncecal("export --material " + (folder_ / "linear.json").string() +
                   " --engine lammps --bounces 4 --max-step-error 0.005 -o " + deck.string());
  ASSERT_EQ(exported.exit_status, 0) << exported.output;
  EXPECT_NE(exported.output.find("EXACT LAW"), std::string::npos) << exported.output;
  ASSERT_EQ(std::system(("cd " + deck.string() +
                         " && lmp -in in.drop -log log.lammps > run.out "
                         "2>&1")
                            .c_str()),
            0)
      << Tail(deck / "run.out");
  const auto verdict = RunBouncecal("export-check " + deck.string());
  EXPECT_NE(verdict.output.find("PASSED: 4 of 4"), std::string::npos) << verdict.output;
}

// What a run's dump.pack holds: the timestep of each frame and the atom count of the last.
struct DumpFrames {
  std::vector<long> timesteps;
  long last_atom_count = -1;
  bool has_all_columns = false;
};

DumpFrames ReadDumpFrames(const fs::path& path) {
  DumpFrames frames;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    line.erase(line.find_last_not_of(' ') + 1);  // LIGGGHTS ends its ATOMS header with a space
    if (line == "ITEM: TIMESTEP" && std::getline(in, line)) {
      frames.timesteps.push_back(std::stol(line));
    }
    if (line == "ITEM: NUMBER OF ATOMS" && std::getline(in, line)) {
      frames.last_atom_count = std::stol(line);
    }
    if (line.rfind("ITEM: ATOMS", 0) == 0) {
      frames.has_all_columns = line == "ITEM: ATOMS id type radius x y z vx vy vz";
    }
  }
  return frames;
}

// The small pour below (150 spheres, 0.03 s), its insertion given as `insertion` (a JSON object).
std::string SmallPourScene(const std::string& snapshot_interval_s,
                           const std::string& insertion = R"({"type": "pour",
                  "region": {"type": "cylinder", "center_m": [0, 0], "radius_m": 0.04,
                             "z_min_m": 0.02, "z_max_m": 0.25},
                  "batch_interval_s": 0.1, "seed": 7})") {
  return R"({
    "format": "bouncecal-scene/1",
    "name": "mpi-smoke",
    "dimension": 3,
    "particles": {"count": 150, "diameter_m": 0.01,
                  "species": [{"name": "steel", "density_kg_per_m3": 7800, "volume_fraction": 1}]},
    "container": {"type": "cylinder", "center_m": [0, 0, 0], "radius_m": 0.05, "height_m": 0.2},
    "insertion": )" +
         insertion + R"(,
    "material": {"contact_law": {"law": "walton-braun",
                                 "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
                 "tangential_stiffness_n_per_m": 1e7, "friction": 0.3, "wall_friction": 0.3},
    "physics": {"tangential": true, "rotation": true, "van_der_waals": false,
                "local_damping": false},
    "time_step_s": 1e-5, "duration_s": 0.03, "gravity_mps2": 9.81,
    "measurement": {"band_m": [0.005, 0.045]},
    "outputs": {"directory": "out", "snapshot_interval_s": )" +
         snapshot_interval_s + R"(}
  })";
}

// A small, short pour (150 spheres, 0.03 s) of the paper's material, exported from a scene file
// through the command line: enough to insert every particle, build contacts with both walls and
// between particles, and cross the boundary between the two ranks' sub-domains (the box is split
// along z). The scene's snapshot interval (0: it asks bouncecal pack for no dumps) decides the
// deck's dump interval, which the run's dump.pack must show.
void ExportSceneAndRunOnTwoProcesses(const fs::path& folder, const std::string& engine,
                                     const std::string& snapshot_interval_s,
                                     const std::vector<long>& expected_dump_steps) {
  fs::create_directories(folder);
  std::ofstream(folder / "small_pour.json") << SmallPourScene(snapshot_interval_s);
  const fs::path deck = folder / "deck";
  const auto exported = RunBouncecal(
      "export --material " + (folder.parent_path() / "card.json").string() + " --engine " + engine +
      " --scene " + (folder / "small_pour.json").string() + " -o " + deck.string());
  ASSERT_EQ(exported.exit_status, 0) << exported.output;
  const std::string executable = engine == "lammps" ? "lmp" : "liggghts";
  const std::string run = "mpirun -np 2 " + executable + " -in in.pack -log log." + engine;
  ASSERT_NE(exported.output.find("cd " + deck.string() + " && " + run), std::string::npos)
      << exported.output;

  // Open MPI refuses to start as root (CI) unless told twice; --oversubscribe lets two ranks run
  // on a machine that reports a single slot.
  const std::string command = "cd " + deck.string() +
                              " && OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                              "mpirun --oversubscribe " + run.substr(7) + " > run.out 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << "end of the output:\n" << Tail(deck / "run.out");
  std::ifstream log(deck / "run.out");
  std::stringstream text;
  text << log.rdbuf();
  EXPECT_NE(text.str().find("1 by 1 by 2 MPI processor grid"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("on 2 procs for 3000 steps with 150 atoms"), std::string::npos)
      << Tail(deck / "run.out");
  std::ifstream data(deck / "final.data");
  std::stringstream data_text;
  data_text << data.rdbuf();
  EXPECT_NE(data_text.str().find("150 atoms"), std::string::npos) << "final.data";

  // docs/export.md promises dump snapshots: every frame in one file, from step 0 to the end.
  const DumpFrames frames = ReadDumpFrames(deck / "dump.pack");
  EXPECT_EQ(frames.timesteps, expected_dump_steps);
  EXPECT_EQ(frames.last_atom_count, 150);
  EXPECT_TRUE(frames.has_all_columns);
}

std::vector<long> EveryNthStep(long every, long last) {
  std::vector<long> steps;
  for (long step = 0; step <= last; step += every) steps.push_back(step);
  return steps;
}

TEST_F(ExportedDeck, LammpsPackingDeckRunsOnTwoMpiProcesses) {
  if (!OnPath("lmp") || !OnPath("mpirun")) {
    GTEST_SKIP() << "LAMMPS (lmp) or mpirun is not installed; scripts/install_deps.sh installs "
                    "lammps, which brings Open MPI";
  }
  // The scene asks for a snapshot every 0.01 s: every 1000 steps of 10 us.
  ExportSceneAndRunOnTwoProcesses(folder_ / "pack-lammps", "lammps", "0.01",
                                  EveryNthStep(1000, 3000));
}

TEST_F(ExportedDeck, LiggghtsPackingDeckRunsOnTwoMpiProcesses) {
  if (!OnPath("liggghts") || !OnPath("mpirun")) {
    GTEST_SKIP() << "LIGGGHTS (liggghts) or mpirun is not installed; scripts/install_deps.sh "
                    "installs liggghts, which brings Open MPI";
  }
  // The scene asks for none: the deck dumps 20 times over the 3000 steps.
  ExportSceneAndRunOnTwoProcesses(folder_ / "pack-liggghts", "liggghts", "0",
                                  EveryNthStep(150, 3000));
}

// docs/packing.md, "Larger than one machine", run as written there: the scene exported with
// `--processes 2`, the deck run by LAMMPS on two MPI ranks, and its final.data brought back as a
// start file of the same scene, which `bouncecal pack --duration-s 0` measures (and a short run
// continues). Every one of the 150 spheres LAMMPS poured must come back, inside the container.
TEST_F(ExportedDeck, SceneRunOnTwoRanksComesBackAsAStartFile) {
  if (!OnPath("lmp") || !OnPath("mpirun")) {
    GTEST_SKIP() << "LAMMPS (lmp) or mpirun is not installed; scripts/install_deps.sh installs "
                    "lammps, which brings Open MPI";
  }
  const fs::path folder = folder_ / "cluster";
  fs::create_directories(folder);
  std::ofstream(folder / "scene.json") << SmallPourScene("0");
  const fs::path deck = folder / "deck";
  const auto exported = RunBouncecal(
      "export --material " + (folder_ / "card.json").string() + " --engine lammps --scene " +
      (folder / "scene.json").string() + " --processes 2 -o " + deck.string());
  ASSERT_EQ(exported.exit_status, 0) << exported.output;
  const std::string command = "cd " + deck.string() +
                              " && mpirun --allow-run-as-root --oversubscribe -np 2 lmp -in "
                              "in.pack -log log.lammps > run.out 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << "end of the output:\n" << Tail(deck / "run.out");

  std::ofstream(folder / "back.json")
      << SmallPourScene("0", R"({"type": "file", "path": "deck/final.data"})");
  const auto measured = RunBouncecal("pack " + (folder / "back.json").string() +
                                     " --duration-s 0 -o " + (folder / "back").string() +
                                     " --json " + (folder / "back" / "measured.json").string());
  ASSERT_EQ(measured.exit_status, 0) << measured.output;
  std::ifstream in(folder / "back" / "measured.json");
  const auto json = nlohmann::json::parse(in);
  EXPECT_EQ(json["particles"], 150);
  EXPECT_EQ(json["steps"], 0);
  // 0.03 s after a pour from 2-25 cm the lowest spheres are in the 0.5-4.5 cm band: a density
  // above zero and below random close packing (0.64) says the file's positions and diameters
  // were read as LAMMPS wrote them (a diameter read as a radius would double it, at least).
  EXPECT_GT(json["packing_density"].get<double>(), 0.0);
  EXPECT_LT(json["packing_density"].get<double>(), 0.64);

  const auto continued = RunBouncecal("pack " + (folder / "back.json").string() +
                                      " --duration-s 0.005 -o " + (folder / "more").string());
  EXPECT_EQ(continued.exit_status, 0) << continued.output;
}

}  // namespace
}  // namespace bouncecal::testing
