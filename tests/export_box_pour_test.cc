// An exported 3D box pour whose insertion region reaches closer to the walls than a radius (300
// tennis balls, region 2 cm inside 0.6 m walls): the deck must start every centre a radius inside
// the box, insert all 300, lose none on two MPI ranks, print real kinetic energies, and settle to
// the packing density `bouncecal pack` gives for the same scene. Skips, with a message, when an
// engine or mpirun is not installed; scripts/install_deps.sh installs both engines.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "external_engine.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kCount = 300;
constexpr double kDiameterM = 0.067;  // a tennis ball: 67 mm, 57.7 g
constexpr double kMassKg = 0.0577;
constexpr double kGravity = 9.81;
constexpr double kTimeStepS = 1e-4;
constexpr double kDurationS = 1.5;
constexpr int kSeed = 1;

double Density() { return kMassKg / (std::numbers::pi * std::pow(kDiameterM, 3) / 6); }

// A tennis ball's card: k = 2e4 N/m gives the ~5 ms wall contact of a real one (so a 0.1 ms step
// resolves a pair contact in ~40 steps), gamma_n = 0.3 its e ~ 0.73.
std::string Card() {
  return R"({
    "format": "bouncecal-material/1",
    "contact_law": {"law": "walton-braun",
                    "parameters": {"stiffness_n_per_m": 2e4, "gamma_n": 0.3}},
    "ball": {"diameter_m": 0.067, "mass_kg": 0.0577}
  })";
}

// The box scene of issue 28. `insertion` is the scene's insertion object; the band measures
// from a radius above the floor to two diameters, inside the ~4 layers the pour settles into.
std::string BoxScene(const std::string& insertion, const std::string& name) {
  return R"({
    "format": "bouncecal-scene/1",
    "name": ")" +
         name + R"(",
    "dimension": 3,
    "particles": {"count": 300, "diameter_m": 0.067,
                  "species": [{"name": "tennis", "density_kg_per_m3": )" +
         std::to_string(Density()) + R"(, "volume_fraction": 1}]},
    "container": {"type": "box", "min_m": [-0.3, -0.3, 0], "max_m": [0.3, 0.3, 0.6]},
    "insertion": )" +
         insertion + R"(,
    "material": {"contact_law": {"law": "walton-braun",
                                 "parameters": {"stiffness_n_per_m": 2e4, "gamma_n": 0.3}},
                 "tangential_stiffness_n_per_m": 2e4, "friction": 0.5, "wall_friction": 0.5},
    "physics": {"tangential": true, "rotation": true, "van_der_waals": false,
                "local_damping": false},
    "time_step_s": 1e-4, "duration_s": 1.5, "gravity_mps2": 9.81,
    "measurement": {"band_m": [0.0335, 0.134], "history_interval_s": 0.05},
    "outputs": {"directory": ")" +
         name + R"(_out", "snapshot_interval_s": 0}
  })";
}

std::string Pour(int seed) {
  return R"({"type": "pour",
              "region": {"type": "box", "min_m": [-0.28, -0.28, 0.05], "max_m": [0.28, 0.28, 0.6]},
              "batch_interval_s": 0.5, "seed": )" +
         std::to_string(seed) + "}";
}

std::string FileInsertion(const fs::path& file) {
  return R"({"type": "file", "path": ")" + file.string() + R"("})";
}

// Runs `bouncecal pack` on a scene file and reads its summary.json.
nlohmann::json Pack(const fs::path& scene, const std::string& name, const std::string& extra = "") {
  const auto run = RunBouncecal("pack " + scene.string() + " " + extra);
  EXPECT_EQ(run.exit_status, 0) << run.output;
  return nlohmann::json::parse(std::ifstream(scene.parent_path() / (name + "_out/summary.json")));
}

// The thermo rows of a log: step, time, atoms, translational and rotational kinetic energy.
struct ThermoRow {
  long step = 0;
  double time_s = 0;
  long atoms = 0;
  double translation_j = 0;
  double rotation_j = 0;
};

std::vector<ThermoRow> ReadThermo(const fs::path& log) {
  std::vector<ThermoRow> rows;
  std::ifstream in(log);
  std::string line;
  bool in_table = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first == "Step") {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    ThermoRow row;
    std::istringstream fields(line);
    if (fields >> row.step >> row.time_s >> row.atoms >> row.translation_j >> row.rotation_j) {
      rows.push_back(row);
    } else {
      in_table = false;
    }
  }
  return rows;
}

class ExportedBoxPour : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(folder_ / "card.json") << Card();
    std::ofstream(folder_ / "box.json") << BoxScene(Pour(kSeed), "box");
  }

  // Exports the scene for `engine`, runs it on two MPI ranks and checks what it inserted, lost
  // and printed; returns the packing density of its final state, measured by bouncecal.
  double ExportRunAndMeasure(const std::string& engine) {
    const fs::path deck = folder_ / ("deck-" + engine);
    const auto exported = RunBouncecal("export --material " + (folder_ / "card.json").string() +
                                       " --engine " + engine + " --scene " +
                                       (folder_ / "box.json").string() + " -o " + deck.string());
    EXPECT_EQ(exported.exit_status, 0) << exported.output;
    // Every sphere of the scene starts from bouncecal's own placement: nothing left to pour.
    EXPECT_NE(exported.output.find("the 300 spheres bouncecal's engine places at t = 0"),
              std::string::npos)
        << exported.output;
    const std::string executable = engine == "lammps" ? "lmp" : "liggghts";
    // Open MPI refuses to start as root (CI) unless told twice; --oversubscribe lets two ranks
    // run on a machine that reports a single slot (as tests/export_engine_test.cc runs them).
    const std::string command = "cd " + deck.string() +
                                " && OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                                "mpirun --oversubscribe -np 2 " +
                                executable + " -in in.pack -log log." + engine + " > run.out 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_EQ(status, 0) << "end of the output:\n" << Tail(deck / "run.out");
    if (status != 0) return 0;

    const std::string out = ReadFileText(deck / "run.out");
    EXPECT_EQ(out.find("Lost atoms"), std::string::npos) << Tail(deck / "run.out");
    EXPECT_NE(out.find("on 2 procs for 15000 steps with 300 atoms"), std::string::npos)
        << Tail(deck / "run.out");
    EXPECT_NE(ReadFileText(deck / "final.data").find("300 atoms"), std::string::npos);

    // Real kinetic energies: until the lowest sphere (its centre at least 0.05 m + r up) meets
    // the floor, after sqrt(2 x 0.05 / g) = 0.101 s, all 300 fall freely from rest without
    // touching (bouncecal placed them apart, and they fall together), so the thermo row at
    // 0.075 s must print N m (g t)^2 / 2 = 4.686 J exactly (velocity Verlet is exact under a
    // constant force; 1e-4 allows for the printed digits) and no spin.
    const auto rows = ReadThermo(deck / ("log." + engine));
    EXPECT_GE(rows.size(), 20u);
    bool checked_free_fall = false;
    for (const auto& row : rows) {
      EXPECT_EQ(row.atoms, kCount) << "step " << row.step;
      if (row.step > 0 && row.time_s < 0.1) {
        const double expected = kCount * 0.5 * kMassKg * std::pow(kGravity * row.time_s, 2);
        EXPECT_NEAR(row.translation_j / expected, 1.0, 1e-4) << "step " << row.step;
        EXPECT_NEAR(row.rotation_j, 0.0, 1e-12) << "step " << row.step;
        checked_free_fall = true;
      }
    }
    EXPECT_TRUE(checked_free_fall) << "no thermo row during the free fall";

    // The final state measured by the same code as bouncecal's own (pack --duration-s 0).
    const fs::path measure = folder_ / (engine + ".json");
    std::ofstream(measure) << BoxScene(FileInsertion(deck / "final.data"), engine);
    const auto summary = Pack(measure, engine, "--duration-s 0");
    EXPECT_EQ(summary.at("particles").get<int>(), kCount);
    return summary.at("packing_density").get<double>();
  }

  const ScratchFolder folder_;
};

// The seed spread of `bouncecal pack` on this scene, measured over seeds 1-8: packing density in
// the band 0.5558 +- 0.0058 (sample standard deviation; range 0.5475-0.5647). The engines start
// from bouncecal's own placement for seed 1 but sum their forces in other orders and
// run the mapped linear spring-dashpot instead of Walton-Braun's hysteresis, so the settling
// diverges after the first collisions and their final state is another sample of the same pour:
// it must lie within 3 SD of the difference of two such samples, 3 sqrt(2) 0.0058 = 0.025, of
// bouncecal's same-seed density (a 1-in-370 false alarm for a normal
// spread). Measured when this test was written: bouncecal 0.5625, LAMMPS 0.5669, LIGGGHTS
// 0.5628 (+0.8 and +0.1 SD); with the density written to more digits (a chaotically different
// run) 0.5607, 0.5673 and 0.5648. Both engines tend to land above the seed mean, within the
// spread; the mapping's other force history inside a contact may explain it (docs/export.md).
constexpr double kSeedSd = 0.0058;

double BouncecalDensity(const fs::path& folder) {
  return Pack(folder / "box.json", "box").at("packing_density").get<double>();
}

TEST_F(ExportedBoxPour, LammpsOnTwoRanksInsertsAll300LosesNoneAndSettlesToBouncecalsDensity) {
  if (!OnPath("lmp") || !OnPath("mpirun")) {
    GTEST_SKIP() << "LAMMPS (lmp) or mpirun is not installed; scripts/install_deps.sh installs "
                    "lammps, which brings Open MPI";
  }
  const double ours = BouncecalDensity(folder_.path());
  const double theirs = ExportRunAndMeasure("lammps");
  std::cout << "packing density: bouncecal " << ours << ", LAMMPS " << theirs << "\n";
  EXPECT_NEAR(theirs, ours, 3 * std::sqrt(2.0) * kSeedSd);
}

TEST_F(ExportedBoxPour, LiggghtsOnTwoRanksInsertsAll300LosesNoneAndSettlesToBouncecalsDensity) {
  if (!OnPath("liggghts") || !OnPath("mpirun")) {
    GTEST_SKIP() << "LIGGGHTS (liggghts) or mpirun is not installed; scripts/install_deps.sh "
                    "installs liggghts, which brings Open MPI";
  }
  const double ours = BouncecalDensity(folder_.path());
  const double theirs = ExportRunAndMeasure("liggghts");
  std::cout << "packing density: bouncecal " << ours << ", LIGGGHTS " << theirs << "\n";
  EXPECT_NEAR(theirs, ours, 3 * std::sqrt(2.0) * kSeedSd);
}

}  // namespace
}  // namespace bouncecal::testing
