// LAMMPS as the referee of bouncecal's 2D packing engine: paper 004's box of 240 disks with
// friction and a viscous dashpot, run from the same start positions in both engines, must settle
// to the same area fraction. The LAMMPS input is the one `bouncecal export --scene` writes (the
// 2D deck: dimension 2, gran/hooke/history, wall/gran, nve/sphere, enforce2d), and both final
// states are measured by the same code (`bouncecal pack --duration-s 0` on each final state).
// Skips, with a message, when lmp is not installed; scripts/install_deps.sh installs it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "external_engine.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

// Paper 004's box and window (docs/packing.md) with the friction case of the cross-check in
// docs/packing.md: k_n = k_t = 100 N/m, viscous damping ratio 0.1, friction 0.364, no van der
// Waals, no local damping, no first-contact stop, dt = 1 us. `insertion` is the JSON of the
// scene's insertion object.
std::string FrictionScene(const std::string& insertion, double duration_s,
                          const std::string& output_dir) {
  return R"({
    "format": "bouncecal-scene/1",
    "name": "referee",
    "dimension": 2,
    "particles": {"count": 240, "diameter_m": 1e-4,
                  "species": [{"name": "steel", "density_kg_per_m3": 7860, "volume_fraction": 1}]},
    "container": {"type": "box", "min_m": [0, 0], "max_m": [0.002, 0.002], "closed_top": true},
    "insertion": )" +
         insertion + R"(,
    "material": {"contact_law": {"law": "linear-dashpot",
                                 "parameters": {"stiffness_n_per_m": 100, "damping_ratio": 0.1}},
                 "tangential_stiffness_n_per_m": 100, "friction": 0.364, "wall_friction": 0.364},
    "physics": {"tangential": true, "rotation": true, "van_der_waals": false,
                "local_damping": false, "stop_at_first_contact": false},
    "time_step_s": 1e-6, "duration_s": )" +
         std::to_string(duration_s) + R"(, "gravity_mps2": 9.81,
    "measurement": {"window": {"min_m": [0.0002, 0.0002], "max_m": [0.0018, 0.0011]},
                    "history_interval_s": 0.01},
    "outputs": {"directory": ")" +
         output_dir + R"("}
  })";
}

std::string FileInsertion(const fs::path& file) {
  return R"({"type": "file", "path": ")" + file.string() + R"("})";
}

struct Measured {
  double area_fraction = 0;
  double coordination = 0;
};

// Runs `bouncecal pack` on the scene text and reads its summary.json.
Measured Pack(const fs::path& folder, const std::string& name, const std::string& scene_text,
              const std::string& extra = "") {
  const fs::path scene = folder / (name + ".json");
  std::ofstream(scene) << scene_text;
  const auto run = RunBouncecal("pack " + scene.string() + " " + extra);
  EXPECT_EQ(run.exit_status, 0) << run.output;
  const auto summary = nlohmann::json::parse(std::ifstream(folder / (name + "_out/summary.json")));
  return {summary.at("packing_density").get<double>(),
          summary.at("mean_coordination").get<double>()};
}

struct Stats {
  double mean = 0;
  double standard_error = 0;
};

Stats MeanAndStandardError(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  Stats s;
  for (double v : values) s.mean += v / n;
  double sum_squares = 0;
  for (double v : values) sum_squares += (v - s.mean) * (v - s.mean);
  s.standard_error = std::sqrt(sum_squares / (n - 1) / n);
  return s;
}

TEST(LammpsReferee, FrictionalDiskPackingAgreesWithinTwoStandardErrors) {
  if (!OnPath("lmp")) {
    GTEST_SKIP() << "LAMMPS (lmp, Debian package lammps) is not installed; "
                    "scripts/install_deps.sh installs it";
  }
  const ScratchFolder root;
  std::ofstream(root / "card.json") << R"({
      "format": "bouncecal-material/1",
      "contact_law": {"law": "linear-dashpot",
                      "parameters": {"stiffness_n_per_m": 100, "damping_ratio": 0.1}},
      "ball": {"diameter_m": 1e-4, "density_kg_per_m3": 7860}
    })";

  // The settling is over by 0.15 s (the paper's steady time; the viscous damping leaves a kinetic
  // energy below 1e-6 of the start's potential energy there), so 0.2 s measures the final state
  // at a third of the cost of the 0.4 s cross-check in docs/packing.md.
  constexpr double kDurationS = 0.2;
  constexpr int kSeeds = 5;
  std::vector<double> ours, theirs, ours_z, theirs_z;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const fs::path folder = root / ("seed" + std::to_string(seed));
    fs::create_directories(folder);
    // The start file, as a user gets it: the random placement measured at t = 0.
    Pack(
        folder, "start",
        FrictionScene(
            R"({"type": "random", "region": {"type": "box", "min_m": [0, 0], "max_m": [0.002, 0.002]},
                 "max_attempts": 900000, "seed": )" +
                std::to_string(seed) + "}",
            kDurationS, "start_out"),
        "--duration-s 0");
    const std::string from_start =
        FrictionScene(FileInsertion(folder / "start_out/particles.csv"), kDurationS, "run_out");
    const Measured run = Pack(folder, "run", from_start);

    const fs::path deck = folder / "deck";
    const auto exported = RunBouncecal("export --material " + (root / "card.json").string() +
                                       " --engine lammps --processes 1 --scene " +
                                       (folder / "run.json").string() + " -o " + deck.string());
    ASSERT_EQ(exported.exit_status, 0) << exported.output;
    ASSERT_EQ(std::system(("cd " + deck.string() +
                           " && nice -n 10 lmp -in in.pack -log log.lammps > run.out 2>&1")
                              .c_str()),
              0)
        << Tail(deck / "run.out");
    const Measured lammps =
        Pack(folder, "lammps", FrictionScene(FileInsertion(deck / "final.data"), 0, "lammps_out"),
             "--duration-s 0");
    ours.push_back(run.area_fraction);
    theirs.push_back(lammps.area_fraction);
    ours_z.push_back(run.coordination);
    theirs_z.push_back(lammps.coordination);
    std::cout << "seed " << seed << ": bouncecal " << run.area_fraction << " (z "
              << run.coordination << "), LAMMPS " << lammps.area_fraction << " (z "
              << lammps.coordination << ")\n";
  }
  const Stats a = MeanAndStandardError(ours);
  const Stats b = MeanAndStandardError(theirs);
  const Stats az = MeanAndStandardError(ours_z);
  const Stats bz = MeanAndStandardError(theirs_z);
  std::cout << "area fraction: bouncecal " << a.mean << " +- " << a.standard_error << ", LAMMPS "
            << b.mean << " +- " << b.standard_error << "\ncoordination: bouncecal " << az.mean
            << " +- " << az.standard_error << ", LAMMPS " << bz.mean << " +- " << bz.standard_error
            << "\n";
  // A settling pack is chaotic: the two engines sum forces in different orders, so after a few
  // ms the same start gives two different packings, as two seeds would. Each engine's mean is
  // therefore uncertain by its standard error over the starts, and two engines that agree give
  // means within two combined standard errors 95 % of the time. With 5 starts that is about
  // 0.013 in area fraction, below the differences the check must catch: friction off (0.863),
  // no damping (0.838) or local damping alpha = 0.7 (0.781) against 0.824 (docs/packing.md).
  const double combined = std::hypot(a.standard_error, b.standard_error);
  EXPECT_LT(std::abs(a.mean - b.mean), 2 * combined);
  EXPECT_LT(std::abs(az.mean - bz.mean), 2 * std::hypot(az.standard_error, bz.standard_error));
  // The standard errors themselves must stay small enough for the check to mean anything.
  EXPECT_LT(2 * combined, 0.02);
}

}  // namespace
}  // namespace bouncecal::testing
