#include "bouncecal/calibrate/material_card.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::calibrate {
namespace {

using bouncecal::testing::ScratchPath;

MaterialCard ExampleCard() {
  MaterialCard card;
  card.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.41}, {"stiffness_n_per_m", 2e7}}};
  card.ball.diameter_m = 0.04;
  card.ball.mass_kg = 0.0027;
  card.implied_restitution = 0.646;
  card.implied_energy_loss = 0.583;
  card.fit.objective = "intervals";
  card.fit.residual = 12.5;
  card.fit.confidence_interval["gamma_n"] = {0.40, 0.42};
  card.fit.drop_height_m = 0.3;
  card.fit.gamma_n_formula = 0.408;
  card.recordings.push_back({"drop.wav", "fnv1a64:0123456789abcdef", 0.3, 2});
  card.tool_version = "0.1.0";
  card.created_utc = "2026-11-21T18:00:00Z";
  return card;
}

TEST(MaterialCard, WriteThenReadGivesTheSameCard) {
  const auto path = ScratchPath("card_roundtrip.json");
  WriteMaterialCard(path, ExampleCard());
  const auto card = ReadMaterialCard(path);
  EXPECT_EQ(card.law.kind, dem::ContactLawKind::kWaltonBraun);
  EXPECT_DOUBLE_EQ(card.law.Get("gamma_n"), 0.41);
  EXPECT_DOUBLE_EQ(card.law.Get("stiffness_n_per_m"), 2e7);
  EXPECT_DOUBLE_EQ(card.ball.MassKg(), 0.0027);
  EXPECT_DOUBLE_EQ(card.fit.confidence_interval.at("gamma_n").second, 0.42);
  EXPECT_DOUBLE_EQ(*card.fit.drop_height_m, 0.3);
  ASSERT_EQ(card.recordings.size(), 1u);
  EXPECT_EQ(card.recordings[0].content_hash, "fnv1a64:0123456789abcdef");
  EXPECT_EQ(card.recordings[0].first_n, 2);
  EXPECT_EQ(card.created_utc, "2026-11-21T18:00:00Z");
}

TEST(MaterialCard, JsonHasTheDocumentedKeysAndUnits) {
  const auto json = ToJson(ExampleCard());
  for (const char* key : {"format", "contact_law", "parameter_units", "ball", "implied", "fit",
                          "recordings", "tool_version", "created_utc"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["format"], "bouncecal-material/1");
  EXPECT_EQ(json["parameter_units"]["stiffness_n_per_m"], "N/m");
  EXPECT_EQ(json["contact_law"]["law"], "walton-braun");
}

TEST(MaterialCard, ContactLawObjectIsReadableByTheDemParserAlone) {
  // Scenes read only "contact_law" with dem::ContactLawConfigFromJson (dem never depends on
  // calibrate), so that object must be complete on its own.
  const auto json = ToJson(ExampleCard());
  const auto law = dem::ContactLawConfigFromJson(json["contact_law"], "test");
  EXPECT_DOUBLE_EQ(law.Get("gamma_n"), 0.41);
}

TEST(MaterialCard, WrongFormatOrMissingFileIsAnInputError) {
  EXPECT_THROW(MaterialCardFromJson({{"format", "other/1"}}, "test"), InputError);
  EXPECT_THROW(ReadMaterialCard("/nonexistent/card.json"), InputError);
}

TEST(MaterialCard, UnwritableTargetIsAnOutputError) {
  EXPECT_THROW(WriteMaterialCard("/nonexistent/folder/card.json", ExampleCard()), OutputError);
}

TEST(MaterialCard, RecordsTheBallTheReleaseAndTheUncertaintyModel) {
  auto card = ExampleCard();
  card.ball_preset = "pingpong-40mm";
  card.fit.drop_height_m.reset();
  card.fit.uncertainty.model = "per-impact scatter + timing";
  card.fit.uncertainty.recordings = 2;
  card.fit.uncertainty.sequences = 3;
  card.fit.uncertainty.duplicates = 1;
  card.fit.uncertainty.per_impact_scatter = 0.02;
  card.fit.uncertainty.effective_dof = 7.5;
  const auto json = ToJson(card);
  EXPECT_EQ(json["ball"]["preset"], "pingpong-40mm");
  EXPECT_TRUE(json["fit"]["drop_height_m"].is_null());
  EXPECT_EQ(json["fit"]["release"], "first-bounce-apex");
  EXPECT_EQ(json["fit"]["uncertainty"]["recordings"], 2);
  const auto read = MaterialCardFromJson(json, "test");
  EXPECT_EQ(read.ball_preset, "pingpong-40mm");
  EXPECT_FALSE(read.fit.drop_height_m.has_value());
  EXPECT_EQ(read.fit.uncertainty.model, "per-impact scatter + timing");
  EXPECT_EQ(read.fit.uncertainty.sequences, 3);
  EXPECT_EQ(read.fit.uncertainty.duplicates, 1);
  EXPECT_DOUBLE_EQ(read.fit.uncertainty.per_impact_scatter, 0.02);
  EXPECT_DOUBLE_EQ(*read.fit.uncertainty.effective_dof, 7.5);
}

TEST(MaterialCard, CardsWithoutTheNewerKeysStillRead) {
  auto json = ToJson(ExampleCard());
  json["fit"].erase("release");
  json["fit"].erase("uncertainty");
  const auto card = MaterialCardFromJson(json, "old card");
  EXPECT_EQ(card.fit.uncertainty.recordings, 0);
  EXPECT_DOUBLE_EQ(*card.fit.drop_height_m, 0.3);
}

TEST(MaterialCard, ReleaseThatContradictsTheDropHeightIsAnInputError) {
  auto json = ToJson(ExampleCard());  // drop_height_m 0.3
  json["fit"]["release"] = "first-bounce-apex";
  EXPECT_THROW(MaterialCardFromJson(json, "test"), InputError);
  json["fit"]["release"] = "sideways";
  EXPECT_THROW(MaterialCardFromJson(json, "test"), InputError);
}

TEST(MakeMaterialCard, NeedsTheBallAndListsARecordingGivenTwiceOnce) {
  FitSummary summary;
  summary.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.4}}};
  FitOptions options;
  EXPECT_THROW(MakeMaterialCard(summary, options, {}, 0), ConfigError);
  EXPECT_THROW(CheckCardOptions(options), ConfigError);
  options.ball_given = true;  // drop.ball is the reference
  options.ball_preset = "steel-10mm";
  const auto path = ScratchPath("card_recording.csv");
  std::ofstream(path) << "onset_s\n0.1\n0.3\n";
  const auto card = MakeMaterialCard(summary, options, {path, path}, 0);
  EXPECT_EQ(card.recordings.size(), 1u);
  EXPECT_EQ(card.fit.uncertainty.recordings, 1);
  EXPECT_EQ(card.ball_preset, "steel-10mm");
  EXPECT_FALSE(card.fit.drop_height_m.has_value());
  EXPECT_EQ(ToJson(card)["fit"]["release"], "first-bounce-apex");
}

// A card states the ball the damping belongs to: its density is the one its mass and size give,
// whichever way the ball was named (issue 28: hollow balls were recorded at steel's 7800 kg/m^3).
TEST(MakeMaterialCard, RecordsTheDensityOfTheBallThatWasUsed) {
  FitSummary summary;
  summary.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.4}}};
  const auto volume = [](double diameter_m) {
    return std::numbers::pi * std::pow(diameter_m, 3) / 6;
  };
  for (const auto& preset : BallPresets()) {
    FitOptions options;
    options.ball_given = true;
    options.ball_preset = std::string(preset.name);
    options.drop.ball = preset.ToBall();
    const auto json = ToJson(MakeMaterialCard(summary, options, {}, 0));
    const auto& ball = json["ball"];
    const double mass =
        preset.mass_kg ? *preset.mass_kg : *preset.density_kg_per_m3 * volume(preset.diameter_m);
    // Both sides are the same double expressions up to one rounding each.
    EXPECT_NEAR(ball["mass_kg"].get<double>(), mass, 1e-12 * mass) << preset.name;
    EXPECT_NEAR(ball["density_kg_per_m3"].get<double>(), mass / volume(preset.diameter_m),
                1e-9 * mass / volume(preset.diameter_m))
        << preset.name;
    EXPECT_DOUBLE_EQ(ball["diameter_m"].get<double>(), preset.diameter_m) << preset.name;
    // Read back, the ball is the same ball.
    const auto read = MaterialCardFromJson(json, "test");
    EXPECT_NEAR(read.ball.MassKg(), mass, 1e-12 * mass) << preset.name;
    EXPECT_NEAR(read.ball.density_kg_per_m3, read.ball.DensityKgPerM3(), 1e-9 * mass)
        << preset.name;
  }
  // The tennis ball of the issue: 57.7 g in 67 mm is 366 kg/m^3.
  FitOptions tennis;
  tennis.ball_given = true;
  tennis.drop.ball = FindBallPreset("tennis").ToBall();
  EXPECT_NEAR(ToJson(MakeMaterialCard(summary, tennis, {}, 0))["ball"]["density_kg_per_m3"], 366.4,
              0.1);
  // A size with a mass (--diameter-m --mass-kg) and a size with a density agree on the same ball.
  FitOptions by_mass, by_density;
  by_mass.ball_given = by_density.ball_given = true;
  by_mass.drop.ball.diameter_m = by_density.drop.ball.diameter_m = 0.05;
  by_mass.drop.ball.mass_kg = 0.05;
  by_density.drop.ball.density_kg_per_m3 = 0.05 / volume(0.05);
  const auto a = ToJson(MakeMaterialCard(summary, by_mass, {}, 0))["ball"];
  const auto b = ToJson(MakeMaterialCard(summary, by_density, {}, 0))["ball"];
  EXPECT_NEAR(a["density_kg_per_m3"].get<double>(), b["density_kg_per_m3"].get<double>(), 1e-9);
  EXPECT_NEAR(a["mass_kg"].get<double>(), b["mass_kg"].get<double>(), 1e-15);
}

TEST(MaterialCard, OldCardWithSteelDensityBesideAHollowBallsMassReadsTheMass) {
  auto json = ToJson(ExampleCard());         // ping-pong sized: 40 mm, 2.7 g
  json["ball"]["density_kg_per_m3"] = 7800;  // what cards wrote before issue 28
  const auto card = MaterialCardFromJson(json, "old card");
  EXPECT_DOUBLE_EQ(card.ball.MassKg(), 0.0027);
  EXPECT_NEAR(card.ball.density_kg_per_m3, 0.0027 / (std::numbers::pi * 0.04 * 0.04 * 0.04 / 6),
              1e-9);
  EXPECT_NEAR(ToJson(card)["ball"]["density_kg_per_m3"].get<double>(), 80.57, 0.01);
}

TEST(UtcTimestamp, FormatsSecondsSinceTheEpochAsIso8601Utc) {
  EXPECT_EQ(UtcTimestamp(0), "1970-01-01T00:00:00Z");
  // 2026-11-21T18:00:00Z: 20778 days after the epoch plus 18 h.
  EXPECT_EQ(UtcTimestamp(20778LL * 86400 + 18 * 3600), "2026-11-21T18:00:00Z");
}

}  // namespace
}  // namespace bouncecal::calibrate
