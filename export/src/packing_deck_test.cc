#include "bouncecal/export/packing_deck.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/error.h"
#include "bouncecal/version.h"

namespace bouncecal::calibrate {
namespace {

ExportMaterial PaperMaterial() {
  ExportMaterial material;
  material.law.kind = dem::ContactLawKind::kWaltonBraun;
  material.law.parameters = {{"stiffness_n_per_m", 1e7}, {"gamma_n", 0.5}};
  material.source = "steel.json";
  return material;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The header's comment lines as sentences again (CommentBlock continues them with "\n#   ").
std::string Unwrapped(const std::string& text) {
  const std::string continuation = "\n#   ";
  std::string sentences;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, continuation.size(), continuation) == 0) {
      sentences += ' ';
      i += continuation.size() - 1;
    } else {
      sentences += text[i];
    }
  }
  return sentences;
}

TEST(MakePackingDeck, DefaultSpecIsThePapersPourAndIsValid) {
  const PackingDeckSpec spec;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, {});
  const std::string& script = deck.files.at(0).content;
  EXPECT_TRUE(Contains(script, "fix             pour all pour 2000 1 12345")) << script;
  EXPECT_TRUE(Contains(script, "zcylinder 0.1")) << script;
  EXPECT_TRUE(Contains(script, "timestep        1e-05"));
  EXPECT_EQ(deck.steps, 300000);  // 3 s of 10 us
  EXPECT_EQ(deck.run_command, "mpirun -np 2 lmp -in in.pack -log log.lammps");
  EXPECT_TRUE(Contains(script, "bouncecal " + std::string(Version())));
  EXPECT_TRUE(Contains(script, "steel.json"));
}

TEST(MakePackingDeck, PairsAndWallsGetTheirOwnMappedCoefficients) {
  const PackingDeckSpec spec;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, {});
  const std::string& script = deck.files.at(0).content;
  // Particle mass from the scene (1 cm steel): the mapping must use it, not the card's ball.
  const double mass = 7800 * std::numbers::pi * 1e-6 / 6;
  const auto mapping = MapWaltonBraun(1e7, 0.5, mass, Engine::kLammps);
  char pair[128], wall[128];
  std::snprintf(pair, sizeof pair, "gran/hooke/history %.12g 10000000 %.12g 0 0.3 0",
                mapping.pair.stiffness_n_per_m, mapping.pair.damping_rate_per_s);
  std::snprintf(wall, sizeof wall, "wall/gran hooke/history %.12g 10000000 %.12g 0 0.3 0 zplane",
                mapping.wall.stiffness_n_per_m, mapping.wall.damping_rate_per_s);
  EXPECT_TRUE(Contains(script, pair)) << pair << "\n" << script;
  EXPECT_TRUE(Contains(script, wall)) << wall << "\n" << script;
}

TEST(MakePackingDeck, CoarseStepIsStatedNotHidden) {
  const auto deck = MakePackingDeck(PaperMaterial(), {}, {});
  // gamma_n(pair) dt = 21940 1/s x 1e-5 s: the header must say the contacts are barely resolved.
  EXPECT_NEAR(deck.time_step_error_bound, 0.219, 0.001);
  EXPECT_TRUE(Contains(deck.files[0].content, "in 5.0 steps")) << deck.files[0].content;
}

// docs/export.md promises snapshots: a scene that asks `bouncecal pack` for none (every shipped
// scene does) must still get them in the deck, 20 over the run, and one that asks gets its own
// interval; the header names the file either way.
TEST(MakePackingDeck, BothEnginesDumpSnapshotsWhetherOrNotTheSceneAsksForThem) {
  for (Engine engine : {Engine::kLammps, Engine::kLiggghts}) {
    SCOPED_TRACE(ToString(engine));
    PackingDeckOptions options;
    options.engine = engine;
    PackingDeckSpec spec;
    spec.snapshot_interval_s = 0;
    auto deck = MakePackingDeck(PaperMaterial(), spec, options);
    // 3 s of 10 us = 300000 steps, dumped every 15000 steps (0.15 s).
    EXPECT_EQ(deck.output_every_steps, 15000);
    EXPECT_TRUE(Contains(deck.files[0].content,
                         "\ndump            snapshots all custom 15000 dump.pack id type radius "
                         "x y z vx vy vz\nrun             300000\n"))
        << deck.files[0].content;
    EXPECT_TRUE(
        Contains(Unwrapped(deck.files[0].content), "dump.pack (snapshots every 0.15 s from t = 0"))
        << deck.files[0].content;
    spec.snapshot_interval_s = 0.1;
    deck = MakePackingDeck(PaperMaterial(), spec, options);
    EXPECT_TRUE(Contains(deck.files[0].content, "snapshots all custom 10000 dump.pack"))
        << deck.files[0].content;
    // A run shorter than 20 steps still dumps every step rather than never.
    spec.snapshot_interval_s = 0;
    spec.duration_s = 5e-5;
    deck = MakePackingDeck(PaperMaterial(), spec, options);
    EXPECT_TRUE(Contains(deck.files[0].content, "snapshots all custom 1 dump.pack"))
        << deck.files[0].content;
  }
}

// The decks travel without the repository: what they cite must be named as bouncecal's own docs,
// never a file outside it.
TEST(MakePackingDeck, NotesCiteBouncecalsPhysicsReference) {
  for (Engine engine : {Engine::kLammps, Engine::kLiggghts}) {
    PackingDeckOptions options;
    options.engine = engine;
    const std::string script =
        Unwrapped(MakePackingDeck(PaperMaterial(), {}, options).files[0].content);
    EXPECT_TRUE(Contains(script, "bouncecal docs/physics.md section 4")) << script;
    EXPECT_FALSE(Contains(script, "PHYSICS.md")) << script;
    EXPECT_FALSE(Contains(script, "../")) << script;
  }
}

TEST(MakePackingDeck, LiggghtsDeckGivesWallsTheirOwnTypeAndPoursInBatches) {
  PackingDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto deck = MakePackingDeck(PaperMaterial(), {}, options);
  const std::string& script = deck.files.at(0).content;
  const double mass = 7800 * std::numbers::pi * 1e-6 / 6;
  const auto mapping = MapWaltonBraun(1e7, 0.5, mass, Engine::kLiggghts);
  char gamma[160];
  std::snprintf(gamma, sizeof gamma, "gamman peratomtypepair 2 %.12g %.12g %.12g %.12g",
                mapping.pair.damping_rate_per_s, mapping.wall.damping_rate_per_s,
                mapping.wall.damping_rate_per_s, mapping.wall.damping_rate_per_s);
  EXPECT_TRUE(Contains(script, gamma)) << gamma << "\n" << script;
  EXPECT_TRUE(Contains(script, "coefficientFriction peratomtypepair 2 0.3 0.3 0.3 0.3"));
  EXPECT_TRUE(Contains(script, "primitive type 2 zcylinder 0.1 0 0"));
  // Batches fall through the 10 cm band in sqrt(2 h / g) = 0.143 s = 14278 steps of 10 us.
  EXPECT_TRUE(Contains(script, "nparticles 2000")) << script;
  EXPECT_TRUE(Contains(script, "insert_every 14278")) << script;
  EXPECT_EQ(deck.run_command, "mpirun -np 2 liggghts -in in.pack -log log.liggghts");
}

TEST(MakePackingDeck, ExplicitInsertionRegionAndBatchIntervalAreUsed) {
  PackingDeckSpec spec;
  spec.insert_radius_m = 0.095;  // the paper's funnel-less pour from 20-30 cm
  spec.insert_z_min_m = 0.2;
  spec.insert_z_max_m = 0.3;
  spec.batch_interval_s = 0.1;
  PackingDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, options);
  EXPECT_TRUE(
      Contains(deck.files[0].content, "region          insert cylinder z 0 0 0.095 0.2 0.3"))
      << deck.files[0].content;
  EXPECT_TRUE(Contains(deck.files[0].content, "insert_every 10000"));  // 0.1 s of 10 us
  spec.insert_radius_m = 0.12;                                         // outside the 0.1 m cylinder
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, options), ConfigError);
}

TEST(MakePackingDeck, PolydisperseScenePoursARangeAndStatesTheSizeDependentRestitution) {
  PackingDeckSpec spec;
  spec.diameter_m = 0.008;
  spec.max_diameter_m = 0.012;
  const auto lammps = MakePackingDeck(PaperMaterial(), spec, {});
  EXPECT_TRUE(Contains(lammps.files[0].content, "diam range 0.008 0.012"))
      << lammps.files[0].content;
  EXPECT_TRUE(Contains(lammps.files[0].content, "POLYDISPERSE")) << lammps.files[0].content;
  // Mapped for the mean diameter (1 cm): the paper's e on the walls for that size.
  EXPECT_NEAR(lammps.expected_restitution, std::sqrt(1.0 / 3.0), 1e-12);
  PackingDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto liggghts = MakePackingDeck(PaperMaterial(), spec, options);
  EXPECT_TRUE(Contains(liggghts.files[0].content,
                       "particledistribution/discrete/numberbased 67867967 5 template1 0.2"))
      << liggghts.files[0].content;
  EXPECT_TRUE(Contains(liggghts.files[0].content, "radius constant 0.0042\n"));  // 8.4 mm class
  spec.max_diameter_m = 0.008;
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, {}), ConfigError);
}

TEST(MakePackingDeck, BoxContainerGetsFourSideWalls) {
  PackingDeckSpec spec;
  spec.container = PackingContainer::kBox;
  spec.box_half_x_m = 0.05;
  spec.box_half_y_m = 0.03;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, {});
  EXPECT_TRUE(Contains(deck.files[0].content, "xplane -0.05 0.05")) << deck.files[0].content;
  EXPECT_TRUE(Contains(deck.files[0].content, "yplane -0.03 0.03"));
}

// Issue 28: LAMMPS' fix pour draws centres anywhere in its region, so a region reaching closer
// to a wall than a radius started spheres inside the wall (lost atoms). The deck's region is the
// scene's shrunk by a largest radius on every side, where bouncecal's engine puts centres.
TEST(MakePackingDeck, PouredCentresKeepARadiusInsideTheScenesRegion) {
  PackingDeckSpec spec;
  spec.container = PackingContainer::kBox;
  spec.box_half_x_m = 0.1;
  spec.box_half_y_m = 0.1;
  spec.insert_half_x_m = 0.098;  // 2 mm from the walls, less than the 5 mm radius
  spec.insert_half_y_m = 0.098;
  const auto lammps = MakePackingDeck(PaperMaterial(), spec, {});
  EXPECT_TRUE(Contains(lammps.files[0].content,
                       "region          insert block -0.093 0.093 -0.093 0.093 0.155 0.245"))
      << lammps.files[0].content;
  PackingDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto liggghts = MakePackingDeck(PaperMaterial(), spec, options);
  // LIGGGHTS keeps whole particles inside the scene's own region.
  EXPECT_TRUE(Contains(liggghts.files[0].content,
                       "region          insert block -0.098 0.098 -0.098 0.098 0.15 0.25"))
      << liggghts.files[0].content;
  EXPECT_TRUE(Contains(liggghts.files[0].content, "all_in yes"));
  // The default cylinder region (the section less a diameter) shrinks the same way.
  const auto cylinder = MakePackingDeck(PaperMaterial(), {}, {});
  EXPECT_TRUE(Contains(cylinder.files[0].content,
                       "region          insert cylinder z 0 0 0.085 0.155 0.245"))
      << cylinder.files[0].content;
}

// fix pour counts a block's volume with a y extent of at least 1 (its quasi-2D rule) and asks
// for vol x volume / (largest sphere) per batch: the deck's fraction must ask for the planned
// batch (a quarter of the band's volume) in its own accounting.
TEST(MakePackingDeck, LammpsPourFractionAsksForThePlannedBatch) {
  PackingDeckSpec spec;
  spec.container = PackingContainer::kBox;
  spec.box_half_x_m = 0.1;
  spec.box_half_y_m = 0.1;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, {});
  // Region 0.09 x 0.09 half-widths, 0.1 m band: quarter = 0.25 x 0.18^2 x 0.1 / 5.236e-7 = 1546.
  // Centres: 0.17 x 1 (not 0.17) x 0.09 m^3; vol = 1546.5 x 5.236e-7 / 0.0153 = 0.05292.
  EXPECT_TRUE(Contains(deck.files[0].content, "vol 0.05292")) << deck.files[0].content;
}

TEST(MakePackingDeck, StartSpheresAreReadNotPouredInBothEngines) {
  PackingDeckSpec spec;
  spec.particle_count = 3;
  spec.start_spheres = {{0, 0, 0.2, 0.01}, {0.02, 0, 0.2, 0.01}, {0, 0.094, 0.005, 0.01}};
  for (Engine engine : {Engine::kLammps, Engine::kLiggghts}) {
    SCOPED_TRACE(ToString(engine));
    PackingDeckOptions options;
    options.engine = engine;
    const auto deck = MakePackingDeck(PaperMaterial(), spec, options);
    ASSERT_EQ(deck.files.size(), 2u);
    const std::string& script = deck.files[0].content;
    EXPECT_EQ(deck.files[0].name, "in.pack");
    EXPECT_TRUE(Contains(script, "read_data       start.data\n")) << script;
    EXPECT_FALSE(Contains(script, "create_box")) << script;
    EXPECT_FALSE(Contains(script, " pour ")) << script;
    EXPECT_FALSE(Contains(script, "insert/rate/region")) << script;
    EXPECT_TRUE(Contains(Unwrapped(script), "the 3 spheres bouncecal's engine places at t = 0"))
        << script;
    EXPECT_EQ(deck.files[1].name, "start.data");
    const std::string& data = deck.files[1].content;
    EXPECT_TRUE(Contains(data, "\n3 atoms\n")) << data;
    // LIGGGHTS declares the wall type; the simulation box is the container plus a diameter.
    EXPECT_TRUE(Contains(data, engine == Engine::kLammps ? "\n1 atom types\n" : "\n2 atom types\n"))
        << data;
    EXPECT_TRUE(Contains(data, "-0.11 0.11 xlo xhi\n")) << data;
    EXPECT_TRUE(Contains(data, "-0.01 0.26 zlo zhi\n")) << data;
    EXPECT_TRUE(Contains(data, "\n3 1 0.01 7800 0 0.094 0.005\n")) << data;
  }
}

TEST(MakePackingDeck, TheRestOfAPourFollowsTheStartAfterTheScenesBatchInterval) {
  PackingDeckSpec spec;
  spec.batch_interval_s = 0.1;
  spec.start_spheres = {{0, 0, 0.2, 0.01}, {0.02, 0, 0.2, 0.01}};
  const auto lammps = MakePackingDeck(PaperMaterial(), spec, {});
  // 0.1 s of 10 us steps, then the 1998 others, then the remaining 290000 steps.
  EXPECT_TRUE(Contains(lammps.files[0].content,
                       "run             10000\nregion          insert cylinder z 0 0 0.085 0.155 "
                       "0.245 units box\nfix             pour all pour 1998 1 12345"))
      << lammps.files[0].content;
  EXPECT_TRUE(Contains(lammps.files[0].content, "run             290000\nwrite_data"));
  PackingDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto liggghts = MakePackingDeck(PaperMaterial(), spec, options);
  // Batches as large as bouncecal's first one (2), every 0.1 s: 20 per second.
  EXPECT_TRUE(
      Contains(liggghts.files[0].content, "nparticles 1998 particlerate 20 insert_every 10000"))
      << liggghts.files[0].content;
  EXPECT_TRUE(Contains(liggghts.files[0].content, "run             290000\nwrite_data"));
}

// The thermo `ke` keyword derives the energy from a temperature whose degrees of freedom were
// counted before any particle was poured, and printed -0: the decks sum it themselves.
TEST(MakePackingDeck, ThermoSumsTheParticlesKineticEnergies) {
  PackingDeckSpec two_d;
  two_d.dimension = 2;
  two_d.container = PackingContainer::kBox;
  two_d.start_data = "data";
  for (const auto& [engine, spec] :
       std::vector<std::pair<Engine, PackingDeckSpec>>{{Engine::kLammps, PackingDeckSpec{}},
                                                       {Engine::kLiggghts, PackingDeckSpec{}},
                                                       {Engine::kLammps, two_d}}) {
    PackingDeckOptions options;
    options.engine = engine;
    const std::string script = MakePackingDeck(PaperMaterial(), spec, options).files[0].content;
    EXPECT_TRUE(Contains(script, "compute         translation all ke\n")) << script;
    EXPECT_TRUE(
        Contains(script, "thermo_style    custom step time atoms c_translation c_rotation\n"))
        << script;
    EXPECT_FALSE(Contains(script, " ke c_rotation")) << script;
  }
}

TEST(MakePackingDeck, APourThatCannotFinishInTheRunIsOneWarningLineWithTheFix) {
  PackingDeckSpec spec;
  spec.duration_s = 0.5;  // batches of 1215 every 0.135 s of fall: the 17th is due at 2.17 s
  spec.particle_count = 20000;
  const auto deck = MakePackingDeck(PaperMaterial(), spec, {});
  std::vector<std::string> warnings;
  for (const auto& note : deck.notes) {
    if (note.rfind("WARNING", 0) == 0) warnings.push_back(note);
  }
  ASSERT_EQ(warnings.size(), 1u) << Unwrapped(deck.files[0].content);
  EXPECT_EQ(warnings[0].find('\n'), std::string::npos);
  EXPECT_TRUE(Contains(warnings[0], "due at t = ")) << warnings[0];
  EXPECT_TRUE(Contains(warnings[0], "after the scene's 0.5 s run")) << warnings[0];
  EXPECT_TRUE(Contains(warnings[0], "raise duration_s above")) << warnings[0];
  spec.particle_count = 2000;
  spec.duration_s = 3;
  for (const auto& note : MakePackingDeck(PaperMaterial(), spec, {}).notes) {
    EXPECT_NE(note.rfind("WARNING", 0), 0u) << note;
  }
}

TEST(MakePackingDeck, StartSpheresOutsideTheContainerOrTooManyAreOneLineErrors) {
  PackingDeckSpec spec;
  spec.particle_count = 1;
  spec.start_spheres = {{0.097, 0, 0.1, 0.01}};  // 3 mm from the 0.1 m cylinder's wall
  try {
    MakePackingDeck(PaperMaterial(), spec, {});
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()),
              "start sphere at (0.097, 0, 0.1) m of diameter 0.01 m is not a radius inside the "
              "container; place every centre at least a radius from the floor and the walls");
  }
  spec.start_spheres = {{0, 0, 0.004, 0.01}};  // 1 mm into the floor
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, {}), ConfigError);
  spec.start_spheres = {{0, 0, 0.1, 0.01}, {0, 0, 0.2, 0.01}};
  try {
    MakePackingDeck(PaperMaterial(), spec, {});
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()),
              "2 start spheres for a scene of 1 particles; give at most 1");
  }
}

// A box that holds a sphere but whose default region (the section less a diameter) leaves no
// room for centres a radius inside it: one line naming the figure and its value.
TEST(MakePackingDeck, ARegionWithNoRoomForCentresIsOneLineError) {
  PackingDeckSpec spec;
  spec.container = PackingContainer::kBox;
  spec.box_half_x_m = 0.012;  // region half-width 0.002 m, less than the 5 mm radius
  try {
    MakePackingDeck(PaperMaterial(), spec, {});
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("scene insertion half-width x minus a radius must be a positive finite "
                            "number of metres, got -0.003",
                            0),
              0u)
        << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

TEST(MakePackingDeck, UnstableStepAndBadSpecsAreConfigErrors) {
  PackingDeckSpec spec;
  spec.time_step_s = 1e-4;  // omega dt = 6.4 for the pair contact
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, {}), ConfigError);
  spec = {};
  spec.insert_z_max_m = spec.insert_z_min_m;
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, {}), ConfigError);
  spec = {};
  spec.particle_count = 0;
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), spec, {}), ConfigError);
  PackingDeckOptions options;
  options.processes = 0;
  EXPECT_THROW(MakePackingDeck(PaperMaterial(), {}, options), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
