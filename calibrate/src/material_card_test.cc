#include "bouncecal/calibrate/material_card.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

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
  card.recordings.push_back({"drop.wav", "fnv1a64:0123456789abcdef"});
  card.tool_version = "0.1.0";
  card.created_utc = "2026-11-21T18:00:00Z";
  return card;
}

TEST(MaterialCard, WriteThenReadGivesTheSameCard) {
  const auto path = std::filesystem::temp_directory_path() / "bouncecal_card_roundtrip.json";
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
  EXPECT_EQ(card.created_utc, "2026-11-21T18:00:00Z");
  std::filesystem::remove(path);
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

TEST(UtcTimestamp, FormatsSecondsSinceTheEpochAsIso8601Utc) {
  EXPECT_EQ(UtcTimestamp(0), "1970-01-01T00:00:00Z");
  // 2026-11-21T18:00:00Z: 20778 days after the epoch plus 18 h.
  EXPECT_EQ(UtcTimestamp(20778LL * 86400 + 18 * 3600), "2026-11-21T18:00:00Z");
}

}  // namespace
}  // namespace bouncecal::calibrate
