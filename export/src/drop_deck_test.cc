#include "bouncecal/export/drop_deck.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/export/drop_deck_check.h"
#include "bouncecal/version.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kSteelBallMassKg = 7800 * std::numbers::pi * 0.01 * 0.01 * 0.01 / 6;

LawMapping PaperLaw(Engine engine) { return MapWaltonBraun(1e7, 0.5, kSteelBallMassKg, engine); }

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string Format12(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.12g", value);
  return buffer;
}

TEST(MakeDropDeck, DefaultOptionsAreValid) {
  const auto deck = MakeDropDeck(PaperLaw(Engine::kLammps), {0.01, kSteelBallMassKg}, {});
  ASSERT_EQ(deck.files.size(), 2u);
  EXPECT_EQ(deck.files[0].name, "in.drop");
  EXPECT_EQ(deck.files[1].name, "deck.json");
  EXPECT_EQ(deck.run_command, "lmp -in in.drop -log log.lammps");
}

TEST(MakeDropDeck, LammpsDeckCarriesWallAndPairCoefficientsAndProvenance) {
  const auto mapping = PaperLaw(Engine::kLammps);
  DropDeckOptions options;
  options.material_source = "cards/steel.json";
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  const std::string& script = deck.files[0].content;
  EXPECT_TRUE(Contains(script, "units           si")) << script;
  EXPECT_TRUE(Contains(script, "fix             integrate all nve/sphere"));
  EXPECT_TRUE(Contains(script, "pair_style      gran/hooke/history " +
                                   Format12(mapping.pair.stiffness_n_per_m) + " 0 " +
                                   Format12(mapping.pair.damping_rate_per_s) + " 0 0 0"))
      << script;
  EXPECT_TRUE(Contains(script, "wall/gran hooke/history " +
                                   Format12(mapping.wall.stiffness_n_per_m) + " 0 " +
                                   Format12(mapping.wall.damping_rate_per_s) + " 0 0 0 zplane"))
      << script;
  EXPECT_TRUE(Contains(script, "file trajectory.txt"));
  EXPECT_TRUE(Contains(script, "bouncecal " + std::string(Version())));
  EXPECT_TRUE(Contains(script, "cards/steel.json"));
  EXPECT_TRUE(Contains(script, "MAPPED LAW: LAMMPS has no Walton-Braun"));
  // The deck travels without the repository: it cites bouncecal's docs by name, nothing outside.
  bool cites_physics = false;
  for (const auto& note : deck.notes) {
    cites_physics = cites_physics || Contains(note, "bouncecal docs/physics.md section 4");
  }
  EXPECT_TRUE(cites_physics);
  EXPECT_FALSE(Contains(script, "PHYSICS.md")) << script;
  EXPECT_TRUE(Contains(script, "timestep        " + Format12(deck.time_step_s)));
  EXPECT_TRUE(Contains(script, "run             " + std::to_string(deck.steps)));
  // Every line of the header is a comment: the engine must not see stray text.
  for (size_t start = 0; start < script.size();) {
    const size_t end = script.find('\n', start);
    const std::string line = script.substr(start, end - start);
    if (line.empty()) break;  // the header ends at the first blank line
    EXPECT_EQ(line[0], '#') << line;
    start = end + 1;
  }
}

TEST(MakeDropDeck, LiggghtsDeckGivesTheWallItsOwnTypePair) {
  const auto mapping = PaperLaw(Engine::kLiggghts);
  DropDeckOptions options;
  options.engine = Engine::kLiggghts;
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  const std::string& script = deck.files[0].content;
  const std::string wall_gamma = Format12(mapping.wall.damping_rate_per_s);
  EXPECT_TRUE(Contains(script, "gamman peratomtypepair 2 " +
                                   Format12(mapping.pair.damping_rate_per_s) + " " + wall_gamma +
                                   " " + wall_gamma + " " + wall_gamma))
      << script;
  EXPECT_TRUE(Contains(script, "model hooke/stiffness"));
  EXPECT_TRUE(Contains(script, "primitive type 2 zplane 0.0"));
  EXPECT_EQ(deck.run_command, "liggghts -in in.drop -log log.liggghts");
}

TEST(MakeDropDeck, DefaultStepKeepsTheRestitutionBoundAndResolvesTheContact) {
  const auto mapping = PaperLaw(Engine::kLammps);
  const DropDeckOptions options;
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  EXPECT_LE(deck.time_step_error_bound, options.max_time_step_error);
  // Rounding the step down to three digits costs at most 1 % of the allowed error.
  EXPECT_GE(deck.time_step_error_bound, 0.99 * options.max_time_step_error);
  EXPECT_GE(mapping.wall_contact_duration_s / deck.time_step_s, kMinStepsPerContact);
  EXPECT_NEAR(deck.expected_restitution, mapping.restitution, 1e-12);
  // Output lines come at most every half contact, so both sides of a contact are sampled.
  EXPECT_LE(deck.output_interval_s, 0.5 * mapping.wall_contact_duration_s);
}

TEST(MakeDropDeck, DeckRecordStatesWhatTheRunMustShow) {
  const auto mapping = PaperLaw(Engine::kLiggghts);
  DropDeckOptions options;
  options.engine = Engine::kLiggghts;
  options.material_source = "card.json";
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  const auto record =
      DropDeckRecordFromJson(nlohmann::json::parse(deck.files.at(1).content), "deck.json");
  EXPECT_EQ(record.engine, "liggghts");
  EXPECT_EQ(record.material_source, "card.json");
  EXPECT_EQ(record.run_command, deck.run_command);
  EXPECT_DOUBLE_EQ(record.ball_radius_m, 0.005);
  EXPECT_DOUBLE_EQ(record.expected_restitution, mapping.restitution);
  EXPECT_DOUBLE_EQ(record.expected_contact_duration_s, mapping.wall_contact_duration_s);
  EXPECT_DOUBLE_EQ(record.time_step_error_bound, deck.time_step_error_bound);
  EXPECT_THROW(DropDeckRecordFromJson(nlohmann::json::parse(R"({"format": "x"})"), "deck.json"),
               InputError);
}

TEST(MakeDropDeck, RunCoversTheRequestedBounces) {
  const auto mapping = PaperLaw(Engine::kLammps);
  DropDeckOptions options;
  options.bounces = 3;
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  // Release to the 4th touch: fall + three flights; the run stops half-way through the third.
  const double g = options.gravity_mps2, e = mapping.restitution;
  const double v1 = std::sqrt(2 * g * options.drop_height_m);
  const double fourth_touch = v1 / g + 2 * v1 * (e + e * e + e * e * e) / g;
  EXPECT_LT(deck.duration_s, fourth_touch);
  EXPECT_GT(deck.duration_s, fourth_touch - 2 * v1 * e * e * e / g);
  EXPECT_GE(deck.steps * deck.time_step_s, deck.duration_s);
}

TEST(MakeDropDeck, GivenTimeStepIsUsedAndItsBoundReported) {
  DropDeckOptions options;
  options.time_step_s = 1e-6;
  const auto mapping = PaperLaw(Engine::kLammps);
  const auto deck = MakeDropDeck(mapping, {0.01, kSteelBallMassKg}, options);
  EXPECT_EQ(deck.time_step_s, 1e-6);
  // gamma_n dt for the wall contact (2 |ln e| / t_c = gamma_n by construction).
  EXPECT_NEAR(deck.time_step_error_bound, mapping.wall.damping_rate_per_s * 1e-6, 1e-12);
}

TEST(MakeDropDeck, BadOptionsAreConfigErrors) {
  const auto mapping = PaperLaw(Engine::kLammps);
  const DeckBall ball{0.01, kSteelBallMassKg};
  DropDeckOptions options;
  options.drop_height_m = -0.1;
  EXPECT_THROW(MakeDropDeck(mapping, ball, options), ConfigError);
  options = {};
  options.time_step_s = 0.0;
  EXPECT_THROW(MakeDropDeck(mapping, ball, options), ConfigError);
  options = {};
  options.time_step_s = 5e-5;  // omega dt = 2.2 for the 71 us wall contact
  EXPECT_THROW(MakeDropDeck(mapping, ball, options), ConfigError);
  options = {};
  options.bounces = 0;
  EXPECT_THROW(MakeDropDeck(mapping, ball, options), ConfigError);
  options = {};
  options.max_time_step_error = 0;
  EXPECT_THROW(MakeDropDeck(mapping, ball, options), ConfigError);
  EXPECT_THROW(MakeDropDeck(mapping, {0.0, kSteelBallMassKg}, {}), ConfigError);
}

TEST(ExportDropDeck, NamesTheCardAndMapsItsLawAtTheDropSpeed) {
  ExportMaterial material;
  material.law.kind = dem::ContactLawKind::kWaltonBraun;
  material.law.parameters = {{"stiffness_n_per_m", 1e7}, {"gamma_n", 0.5}};
  material.diameter_m = 0.01;
  material.mass_kg = kSteelBallMassKg;
  material.source = "lab/steel-on-copper.json";
  const auto deck = ExportDropDeck(material, {});
  EXPECT_TRUE(Contains(deck.files[0].content, "material card: lab/steel-on-copper.json"));
  EXPECT_NEAR(deck.expected_restitution, std::sqrt(1.0 / 3.0), 1e-12);
  material.law.parameters["gamma_n"] = 1.0;  // sticks: no spring-dashpot can match it
  EXPECT_THROW(ExportDropDeck(material, {}), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
