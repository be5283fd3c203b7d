// A program built against the installed bouncecal package (find_package or pkg-config), the way
// docs/install.md describes. It touches every library: a recording is read and its impacts
// detected (audio), turned into restitution and energy loss (calibrate), converted to the
// contact law's damping (dem_model), mapped to LAMMPS' spring-dashpot (export), a
// one-particle scene falls freely in the packing engine (dem), and an impact list is read for the
// synthesiser (synth). tests/consumer/run_consumer_test.sh
// checks the printed figures.
//
//   consumer RECORDING DROP_HEIGHT_M
#include <bouncecal/audio/impact_csv.h>
#include <bouncecal/calibrate/restitution.h>
#include <bouncecal/calibrate/sequence_input.h>
#include <bouncecal/dem/laws/walton_braun.h>
#include <bouncecal/dem/packing.h>
#include <bouncecal/dem/scene.h>
#include <bouncecal/error.h>
#include <bouncecal/export/law_mapping.h>
#include <bouncecal/version.h>

#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

namespace {

// Energy loss of the first three impacts of the recording's first bounce sequence, with the
// paper's convention: the drop height gives the flight before impact 1.
double MeanEnergyLoss(const std::string& recording, double drop_height_m) {
  const auto sequences = bouncecal::calibrate::LoadSequences({recording});
  std::vector<bouncecal::calibrate::TimedImpact> impacts = sequences.front().impacts;
  bouncecal::calibrate::RestitutionOptions options;
  options.drop_height_m = drop_height_m;
  const auto analysis = bouncecal::calibrate::AnalyzeRestitution(impacts, options);
  if (!analysis.energy_loss_mean_first_n) {
    throw bouncecal::InputError(recording + ": fewer than three impacts with a restitution");
  }
  return *analysis.energy_loss_mean_first_n;
}

struct FreeFall {
  double duration_s = 0;
  double speed_mps = 0;
};

// One sphere released from rest in an empty cylinder for 0.05 s: it never reaches the floor, so
// its final speed is g t (velocity Verlet is exact under a constant force).
FreeFall FallInTheEngine() {
  const auto scene = bouncecal::dem::SceneFromJson(nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 1, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.2},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.02, "z_min_m": 0.1, "z_max_m": 0.12}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5, "duration_s": 0.05, "gravity_mps2": 9.81,
    "measurement": {"band_m": [0.005, 0.02]}
  })"),
                                                   "consumer scene");
  const auto summary = bouncecal::dem::RunPacking(scene);
  return {summary.simulated_s, -summary.final_state.velocity_mps.at(0)[2]};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer RECORDING DROP_HEIGHT_M\n");
    return 3;
  }
  try {
    const double eta = MeanEnergyLoss(argv[1], std::atof(argv[2]));
    // The paper's law loses eta = 2 gamma_n / (1 + gamma_n) per impact at any speed
    // (docs/physics.md section 2).
    const double gamma_n = eta / (2 - eta);
    const bouncecal::dem::WaltonBraun law({.stiffness_n_per_m = 1e7, .gamma_n = gamma_n});
    const double mass_kg = 7800 * std::numbers::pi * 1e-6 / 6;  // 1 cm steel ball
    const double restitution = law.ClosedFormRestitution(mass_kg, 0.005, 1.0).value();
    // The engines have no Walton-Braun law: the wall contact of the deck's spring-dashpot keeps
    // its e (and t_c).
    const auto mapping = bouncecal::calibrate::MapWaltonBraun(
        1e7, gamma_n, mass_kg, bouncecal::calibrate::Engine::kLammps);
    const double export_restitution = bouncecal::calibrate::Restitution(mapping.wall);
    const FreeFall fall = FallInTheEngine();
    // What `bouncecal synth --impacts` reads: two impacts, the second slower.
    const auto impacts = bouncecal::audio::ParseImpactCsv(
        "onset_s,impact_speed_mps\n0.1,2.0\n0.5,1.5\n", "consumer");
    std::printf("bouncecal %s\n", std::string(bouncecal::Version()).c_str());
    std::printf("energy_loss_mean_first_3 %.9f\n", eta);
    std::printf("gamma_n %.6f\n", gamma_n);
    std::printf("law_restitution %.9f\n", restitution);
    std::printf("export_restitution %.9f\n", export_restitution);
    std::printf("free_fall_s %.9f\n", fall.duration_s);
    std::printf("free_fall_speed_mps %.12f\n", fall.speed_mps);
    std::printf("synth_impacts %zu\n", impacts.size());
  } catch (const bouncecal::Error& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 2;
  }
  return 0;
}
