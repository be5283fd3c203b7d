#include "bouncecal/dem/packing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

// A small 3D pour: 120 steel spheres d = 1 cm dropped into a 6 cm square box.
nlohmann::json SmallPour() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "name": "small_pour",
    "particles": {"count": 120, "diameter_m": 0.01,
                  "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "box", "min_m": [0, 0, 0], "max_m": [0.06, 0.06, 0.3]},
    "insertion": {"type": "random", "seed": 4,
                  "region": {"type": "box", "min_m": [0, 0, 0.03], "max_m": [0.06, 0.06, 0.12]}},
    "material": {"contact_law": {"law": "walton-braun",
                                 "parameters": {"stiffness_n_per_m": 1e6, "gamma_n": 0.5}},
                 "tangential_stiffness_n_per_m": 1e6, "friction": 0.3},
    "physics": {"tangential": true, "rotation": true},
    "time_step_s": 1e-5,
    "duration_s": 0.5,
    "gravity_mps2": 9.81,
    "measurement": {"band_m": [0.005, 0.025], "history_interval_s": 0.05}
  })");
}

TEST(PackOptions, DefaultsAreValid) { EXPECT_NO_THROW(PackOptions{}.Validate()); }

TEST(PackOptions, BadThreadCountIsAConfigError) {
  PackOptions options;
  options.threads = 0;
  EXPECT_THROW(options.Validate(), ConfigError);
}

TEST(RunPacking, SmallPourComesToRestAtAPhysicalDensity) {
  const Scene scene = SceneFromJson(SmallPour(), "small_pour.json");
  PackOptions options;
  options.threads = 2;
  const PackSummary summary = RunPacking(scene, options);
  ASSERT_EQ(summary.stop_reason, PackStopReason::kDuration) << summary.message;
  EXPECT_EQ(summary.particles, 120);
  EXPECT_EQ(summary.steps, 50000);
  // At rest: the pour released about 120 m g 5 cm of potential energy (0.24 J; the flow peaks
  // at 0.14 J of motion); less than 1e-4 of it is left (a mean speed of about 3 mm/s). The
  // residue at 0.5 s is set by the last small rearrangements, which are chaotic: over seeds 1-4
  // and both particle orderings it was 2e-9 to 4.8e-6 J, so the bound keeps a 5x margin and is
  // still four orders below the flowing state. (The undamped tangential springs keep a small
  // jitter, as in LAMMPS gran/hooke/history without tangential damping.)
  const double m = 7800 * 3.14159265358979 / 6 * 1e-6;
  EXPECT_LT(summary.kinetic_energy_j, 1e-4 * 120 * m * 9.81 * 0.05);
  // Poured frictional spheres in a box 6 d wide: between random loose packing near walls
  // (about 0.5; the walls loosen the first layers) and random close packing (0.64).
  EXPECT_GT(summary.packing_density, 0.50);
  EXPECT_LT(summary.packing_density, 0.66);
  // Every sphere at rest on the floor or on others touches at least one neighbour or a wall;
  // the mean in a frictional pack is between 4 and 6.5 (isostatic frictional 4, frictionless 6).
  EXPECT_GT(summary.coordination.mean, 3.5);
  EXPECT_LT(summary.coordination.mean, 6.5);
  EXPECT_TRUE(summary.warnings.empty()) << summary.warnings.front();
  // The density history starts empty in the band and ends at the final value.
  ASSERT_GE(summary.history.size(), 2u);
  EXPECT_EQ(summary.history.front().packing_density, 0.0);
  EXPECT_DOUBLE_EQ(summary.history.back().packing_density, summary.packing_density);
}

// Single-precision contacts (PackOptions::single_precision_contacts) change the trajectory, not
// the packing: a pour in single is another draw from the distribution of the double pours.
// Over insertion seeds 1-10 of this pour (0.5 s) double gave a band density of 0.547 with a
// standard deviation of 0.0071 and a coordination of 4.47 with 0.137, single 0.547 with 0.0056
// and 4.46 with 0.141; single against double for the same seed differed by up to 0.0175 and
// 0.23, as two seeds do. Two independent draws differ with a standard deviation of sqrt(2) times
// the seed one, so the bounds are three of those (0.030 and 0.58): a precision that moved the
// pack by more would be a change of physics, not of rounding. The rest bound is the one of the
// double pour (SmallPourComesToRestAtAPhysicalDensity), 2.4e-5 J; over the ten seeds single
// ended at 1.9e-8 to 1.8e-5 J, double at 1.6e-8 to 8.5e-6 J (this seed: 8.6e-7 and 1.6e-8 J).
TEST(RunPacking, SinglePrecisionContactsPackLikeDoubleWithinTheSeedSpread) {
  const Scene scene = SceneFromJson(SmallPour(), "small_pour.json");
  PackOptions double_options;
  PackOptions single_options;
  single_options.single_precision_contacts = true;
  const PackSummary reference = RunPacking(scene, double_options);
  const PackSummary single = RunPacking(scene, single_options);
  ASSERT_EQ(single.stop_reason, PackStopReason::kDuration) << single.message;
  // It did run another arithmetic: the pairs went through float.
  EXPECT_NE(single.state_digest, reference.state_digest);
  EXPECT_NEAR(single.packing_density, reference.packing_density, 3 * std::sqrt(2.0) * 0.0071);
  EXPECT_NEAR(single.coordination.mean, reference.coordination.mean, 3 * std::sqrt(2.0) * 0.137);
  const double m = 7800 * 3.14159265358979 / 6 * 1e-6;
  EXPECT_LT(single.kinetic_energy_j, 1e-4 * 120 * m * 9.81 * 0.05);
  // The run says which arithmetic it used.
  const auto says_single = [](const PackSummary& summary) {
    return std::any_of(summary.notes.begin(), summary.notes.end(), [](const std::string& note) {
      return note.find("single precision") != std::string::npos;
    });
  };
  EXPECT_TRUE(says_single(single));
  EXPECT_FALSE(says_single(reference));
}

TEST(RunPacking, RunCutShortWhileParticlesFallWarnsThatTheyAreNotAtRest) {
  // At 0.1 s the spheres of SmallPour are still falling (they start 3-12 cm up): the measures
  // describe a moving state, and the summary says so.
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.1;
  const auto summary = RunPacking(SceneFromJson(json, "cut.json"));
  ASSERT_EQ(summary.stop_reason, PackStopReason::kDuration);
  ASSERT_EQ(summary.warnings.size(), 1u);
  EXPECT_NE(summary.warnings[0].find("not come to rest"), std::string::npos) << summary.warnings[0];
}

TEST(RunPacking, SameSeedGivesByteIdenticalResultsForAnyThreadCount) {
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.05;
  const Scene scene = SceneFromJson(json, "small_pour.json");
  PackOptions two;
  two.threads = 2;
  PackOptions one;
  one.threads = 1;
  const auto a = RunPacking(scene, two);
  const auto b = RunPacking(scene, two);
  const auto c = RunPacking(scene, one);
  ASSERT_EQ(a.final_state.size(), b.final_state.size());
  for (std::size_t i = 0; i < a.final_state.size(); ++i) {
    EXPECT_EQ(a.final_state.position_m[i], b.final_state.position_m[i]) << i;
    EXPECT_EQ(a.final_state.position_m[i], c.final_state.position_m[i]) << i;
    EXPECT_EQ(a.final_state.velocity_mps[i], c.final_state.velocity_mps[i]) << i;
  }
  EXPECT_EQ(a.kinetic_energy_j, c.kinetic_energy_j);
}

TEST(RunPacking, OtherSeedGivesAnotherPacking) {
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.0;
  const Scene first = SceneFromJson(json, "a.json");
  json["insertion"]["seed"] = 5;
  const Scene second = SceneFromJson(json, "b.json");
  EXPECT_NE(RunPacking(first).final_state.position_m[0],
            RunPacking(second).final_state.position_m[0]);
}

TEST(RunPacking, OverfullRandomRegionIsAConfigError) {
  nlohmann::json json = SmallPour();
  json["insertion"]["region"]["max_m"] = {0.06, 0.06, 0.04};
  json["insertion"]["max_attempts"] = 100000;
  const Scene scene = SceneFromJson(json, "full.json");
  EXPECT_THROW(RunPacking(scene), ConfigError);
}

TEST(RunPacking, StepBeyondTheNormalLimitIsRefusedAndPastHalfOfEitherLimitWarns) {
  // SmallPour: m = 7800 pi/6 (0.01)^3 = 4.084e-3 kg. Walton-Braun loads with (1 + gamma) k, so a
  // pair (m/2) is stable for dt < 2 sqrt((m/2) / (1.5 k)) = 7.38e-5 s at k = 1e6. The tangential
  // spring of two rolling spheres, 1/m_t = 2 (1 + 2.5) / m, allows dt < 2 sqrt(m / (7 k_t)) =
  // 4.83e-5 s: beyond it sticking contacts chatter until they slide, so it only warns.
  const double mass = 7800 * 3.14159265358979323846 / 6 * 1e-6;
  const double normal_limit = 2 * std::sqrt(mass / 2 / (1.5 * 1e6));
  const double tangential_limit = 2 * std::sqrt(mass / (7 * 1e6));
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.0;
  const auto fine = RunPacking(SceneFromJson(json, "ok.json"));
  EXPECT_NEAR(fine.time_step_limit_s, normal_limit, 1e-12 * normal_limit);
  EXPECT_NEAR(fine.tangential_time_step_limit_s, tangential_limit, 1e-12 * tangential_limit);
  EXPECT_TRUE(fine.warnings.empty());
  json["time_step_s"] = 1.05 * normal_limit;
  try {
    RunPacking(SceneFromJson(json, "coarse.json"));
    ADD_FAILURE() << "a step 5 % beyond the normal limit ran";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("coarse.json: time_step_s"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("normal contact"), std::string::npos);
  }
  // Past half the tangential limit (0.46 of the normal one): sticking contacts are resolved by
  // too few steps and slip, which settles packs denser (docs/packing.md), so it warns.
  json["time_step_s"] = 0.7 * tangential_limit;
  const auto slipping = RunPacking(SceneFromJson(json, "slip.json"));
  ASSERT_EQ(slipping.warnings.size(), 1u);
  EXPECT_NE(slipping.warnings[0].find("too few steps"), std::string::npos) << slipping.warnings[0];
  // Past half the normal limit as well (0.92 of the tangential one): several contacts stiffen a
  // pack, and the slip warning stays.
  json["time_step_s"] = 0.6 * normal_limit;
  const auto coarse = RunPacking(SceneFromJson(json, "coarse_ok.json"));
  ASSERT_EQ(coarse.warnings.size(), 2u);
  EXPECT_NE(coarse.warnings[0].find("several contacts"), std::string::npos) << coarse.warnings[0];
  EXPECT_NE(coarse.warnings[1].find("too few steps"), std::string::npos) << coarse.warnings[1];
  json["time_step_s"] = 0.95 * normal_limit;  // and beyond the tangential limit: chatter
  const auto chattering = RunPacking(SceneFromJson(json, "chatter.json"));
  ASSERT_EQ(chattering.warnings.size(), 2u);
  EXPECT_NE(chattering.warnings[1].find("will oscillate"), std::string::npos)
      << chattering.warnings[1];
}

TEST(RunPacking, PackThatGainsEnergyBelowTheSingleContactLimitStopsAsUnstable) {
  // A frictionless pour at 0.9 of the single-contact limit: each sphere held by several
  // contacts is a stiffer oscillator than one contact, so the settling pack gains energy from
  // the integrator. The kinetic energy passes twice what the spheres brought in (their fall,
  // about 120 * 4.08e-3 kg * 9.81 * 0.08 m = 0.38 J) long before any sphere crosses half its
  // radius per step; before the energy budget this run finished "fine" with the spheres flung
  // out of the box.
  const double mass = 7800 * 3.14159265358979323846 / 6 * 1e-6;
  const double normal_limit = 2 * std::sqrt(mass / 2 / (1.5 * 1e6));
  nlohmann::json json = SmallPour();
  json["physics"]["tangential"] = false;
  json["physics"]["rotation"] = false;
  json["time_step_s"] = 0.9 * normal_limit;
  json["duration_s"] = 2.0;
  const auto summary = RunPacking(SceneFromJson(json, "stiff_pack.json"));
  EXPECT_EQ(summary.stop_reason, PackStopReason::kUnstable);
  EXPECT_NE(summary.message.find("kinetic energy"), std::string::npos) << summary.message;
  // Half the limit settles: the budget does not stop a sound run.
  json["time_step_s"] = 0.5 * normal_limit;
  json["duration_s"] = 0.5;
  EXPECT_EQ(RunPacking(SceneFromJson(json, "sound_pack.json")).stop_reason,
            PackStopReason::kDuration);
}

TEST(RunPacking, RunawayParticlesStopTheRunAsUnstableInsteadOfFinishingWithAbsurdNumbers) {
  // Forced past the refusal with a step 3x the limit, the pour gains energy at every contact:
  // the run must stop as unstable once a particle moves half its radius per step (250 m/s
  // here), not finish "fine" with particles kilometres away.
  nlohmann::json json = SmallPour();
  json["time_step_s"] = 1.5e-4;
  json["duration_s"] = 2.0;
  PackOptions options;
  options.allow_unstable_step = true;
  const auto summary = RunPacking(SceneFromJson(json, "unstable.json"), options);
  EXPECT_EQ(summary.stop_reason, PackStopReason::kUnstable);
  EXPECT_NE(summary.message.find("half its radius per step"), std::string::npos) << summary.message;
}

TEST(RunPacking, VanDerWaalsThatOverwhelmsTheContactsIsRefused) {
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.0;
  json["physics"]["van_der_waals"] = true;
  EXPECT_NO_THROW(RunPacking(SceneFromJson(json, "vdw.json")));  // 4e-10 m gap: a tiny pull
  // The smallest gap allowed, 1e-12 m, pulls with A R / (6 h^2) = 21.1e-20 * 2.5e-3 / 6e-24 =
  // 88 N: more than soft contacts (k = 1e3 N/m) push back at 10 % of R, 1e3 * 2.5e-4 = 0.25 N.
  json["material"]["vdw_min_gap_m"] = 1e-12;
  json["material"]["contact_law"]["parameters"]["stiffness_n_per_m"] = 1e3;
  EXPECT_THROW(RunPacking(SceneFromJson(json, "vdw.json")), ConfigError);
}

TEST(Dump, LammpsDumpHasOneLinePerParticle) {
  nlohmann::json json = SmallPour();
  json["duration_s"] = 0.0;
  const Scene scene = SceneFromJson(json, "dump.json");
  const auto summary = RunPacking(scene);
  std::ostringstream out;
  WriteLammpsDump(out, summary.final_state, scene);
  const std::string text = out.str();
  EXPECT_EQ(text.rfind("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n120\n", 0), 0u);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 9 + 120);
}

}  // namespace
}  // namespace bouncecal::dem
