#include "bouncecal/export/export_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::calibrate {
namespace {

using bouncecal::testing::ScratchPath;

nlohmann::json PaperCard() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-material/1",
    "contact_law": {"law": "walton-braun",
                    "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
    "ball": {"diameter_m": 0.01, "density_kg_per_m3": 7800, "mass_kg": null},
    "implied": {"restitution": 0.5773502691896257, "energy_loss": 0.6666666666666667},
    "fit": {"objective": "mean-energy-loss", "drop_height_m": 0.2},
    "tool_version": "0.1.0"
  })");
}

// The message of the error `call` throws as E, or "" when it throws nothing.
template <typename E, typename F>
std::string MessageOf(F call) {
  try {
    call();
  } catch (const E& error) {
    return error.what();
  }
  return "";
}

TEST(ExportMaterialFromJson, ReadsLawBallAndImpliedRestitution) {
  const auto material = ExportMaterialFromJson(PaperCard(), "card.json");
  EXPECT_EQ(material.law.kind, dem::ContactLawKind::kWaltonBraun);
  EXPECT_EQ(material.law.Get("gamma_n"), 0.5);
  EXPECT_EQ(material.diameter_m, 0.01);
  // Mass from the density: rho pi d^3 / 6 = 4.084 g (docs/physics.md), to rounding.
  EXPECT_NEAR(material.mass_kg, 7800 * std::numbers::pi * 1e-6 / 6, 1e-15);
  ASSERT_TRUE(material.implied_restitution.has_value());
  EXPECT_NEAR(*material.implied_restitution, std::sqrt(1.0 / 3.0), 1e-12);
  EXPECT_EQ(material.source, "card.json");
  EXPECT_EQ(material.drop_height_m, 0.2);
}

TEST(ExportMaterialFromJson, ExplicitMassOverridesTheDensity) {
  auto card = PaperCard();
  card["ball"]["mass_kg"] = 0.005;
  EXPECT_EQ(ExportMaterialFromJson(card, "card.json").mass_kg, 0.005);
}

TEST(ExportMaterialFromJson, WrongFormatIsAnInputErrorNamingFileAndKey) {
  auto card = PaperCard();
  card["format"] = "something-else/2";
  const auto message = MessageOf<InputError>([&] { ExportMaterialFromJson(card, "my.json"); });
  EXPECT_NE(message.find("my.json"), std::string::npos) << message;
  EXPECT_NE(message.find("\"format\""), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(ExportMaterialFromJson, OutOfRangeLawParameterIsAnInputErrorNamingFileAndParameter) {
  auto card = PaperCard();
  card["contact_law"]["parameters"]["gamma_n"] = 1.5;
  const auto message = MessageOf<InputError>([&] { ExportMaterialFromJson(card, "my.json"); });
  EXPECT_NE(message.find("my.json: contact_law"), std::string::npos) << message;
  EXPECT_NE(message.find("gamma_n"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(ExportMaterialFromJson, MissingOrBadBallKeysAreInputErrorsNamingTheKey) {
  auto card = PaperCard();
  card["ball"].erase("diameter_m");
  auto message = MessageOf<InputError>([&] { ExportMaterialFromJson(card, "my.json"); });
  EXPECT_NE(message.find("my.json: ball"), std::string::npos) << message;
  EXPECT_NE(message.find("diameter_m"), std::string::npos) << message;

  card = PaperCard();
  card["ball"]["density_kg_per_m3"] = -7800;
  message = MessageOf<InputError>([&] { ExportMaterialFromJson(card, "my.json"); });
  EXPECT_NE(message.find("density_kg_per_m3"), std::string::npos) << message;

  card = PaperCard();
  card.erase("contact_law");
  message = MessageOf<InputError>([&] { ExportMaterialFromJson(card, "my.json"); });
  EXPECT_NE(message.find("contact_law"), std::string::npos) << message;
}

TEST(ReadExportMaterial, MissingFileAndInvalidJsonAreInputErrorsNamingTheFile) {
  EXPECT_NE(MessageOf<InputError>([] {
              ReadExportMaterial("/nonexistent/card.json");
            }).find("/nonexistent/card.json"),
            std::string::npos);
  const auto path = ScratchPath("not_json.json");
  std::ofstream(path) << "{ this is not json";
  const auto message = MessageOf<InputError>([&] { ReadExportMaterial(path); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
}

}  // namespace
}  // namespace bouncecal::calibrate
