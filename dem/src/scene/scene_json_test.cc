#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

nlohmann::json Minimal() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 10, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.1, "height_m": 0.2},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.09, "z_min_m": 0.1, "z_max_m": 0.2}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5,
    "duration_s": 0.1,
    "measurement": {"band_m": [0.005, 0.045]}
  })");
}

// The InputError message for a scene (a malformed scene file), or "" when it parses.
std::string ErrorOf(const nlohmann::json& json) {
  try {
    SceneFromJson(json, "scene.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

bool Mentions(const std::string& message, const std::string& text) {
  return message.find(text) != std::string::npos;
}

TEST(SceneJson, MinimalSceneTakesDocumentedDefaults) {
  const Scene scene = SceneFromJson(Minimal(), "dir/scene.json");
  EXPECT_EQ(scene.dimension, 3);
  EXPECT_EQ(scene.particles.count, 10);
  EXPECT_EQ(scene.container.kind, ContainerKind::kCylinder);
  EXPECT_TRUE(scene.physics.tangential);
  EXPECT_TRUE(scene.physics.rotation);
  EXPECT_FALSE(scene.physics.van_der_waals);
  EXPECT_FALSE(scene.physics.local_damping);
  EXPECT_FALSE(scene.physics.stop_at_first_contact);
  EXPECT_EQ(scene.measurement.contact_tolerance, 1.0005);
  EXPECT_EQ(scene.outputs.directory, std::filesystem::path("dir/scene_out"));
  EXPECT_EQ(scene.material.law.kind, ContactLawKind::kWaltonBraun);
}

TEST(SceneJson, UnknownKeyIsRejectedWithItsName) {
  auto json = Minimal();
  json["material"]["frictoin"] = 0.3;
  const auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "scene.json")) << message;
  EXPECT_TRUE(Mentions(message, "material.frictoin")) << message;
  EXPECT_TRUE(Mentions(message, "friction")) << message;  // lists the valid keys
  json = Minimal();
  json["colour"] = "red";
  EXPECT_TRUE(Mentions(ErrorOf(json), "'colour'"));
}

TEST(SceneJson, MissingWrongTypeAndOutOfRangeValuesNameTheKey) {
  auto json = Minimal();
  json["particles"].erase("count");
  auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "particles.count: is missing")) << message;

  json = Minimal();
  json["time_step_s"] = "fast";
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "time_step_s: must be a number")) << message;

  json = Minimal();
  json["container"]["radius_m"] = -0.1;
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "container.radius_m")) << message;
  EXPECT_TRUE(Mentions(message, "outside the valid range")) << message;

  json = Minimal();
  json["particles"]["species"][0]["density_kg_per_m3"] = 0;
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "particles.species[0].density_kg_per_m3")) << message;

  json = Minimal();
  json["material"]["contact_law"]["parameters"] = {{"gamma_n", 1.5}};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "gamma_n")) << message;
}

TEST(SceneJson, EveryMessageIsOneLine) {
  auto json = Minimal();
  json["measurement"]["band_m"] = {0.05, 0.01};
  const auto message = ErrorOf(json);
  EXPECT_FALSE(message.empty());
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(SceneJson, HugeParticleCountIsRefusedWithTheMemoryItNeeds) {
  auto json = Minimal();
  json["particles"]["count"] = 2'000'000'000;
  const auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "GB")) << message;
  EXPECT_TRUE(Mentions(message, "particles.count")) << message;
}

TEST(SceneJson, WholeNumbersMayBeWrittenAsFloatsButNotFractionsOrHugeIntegers) {
  auto json = Minimal();
  json["particles"]["count"] = 1e2;  // as the docs write max_attempts: 1e7
  json["insertion"]["max_attempts"] = 1e7;
  json["insertion"]["seed"] = 18446744073709551615ULL;  // above int64: must not wrap negative
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.seed: 18446744073709551615 is outside"))
      << ErrorOf(json);
  json["insertion"]["seed"] = 12;
  const Scene scene = SceneFromJson(json, "scene.json");
  EXPECT_EQ(scene.particles.count, 100);
  EXPECT_EQ(scene.insertion.max_attempts, 10'000'000);
  json["insertion"]["max_attempts"] = 2.5;
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.max_attempts: must be an integer"));
  json["insertion"]["max_attempts"] = 1e300;
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.max_attempts: 1e+300 is outside"))
      << ErrorOf(json);
}

TEST(SceneJson, RotationWithoutTangentialForceIsRejected) {
  auto json = Minimal();
  json["physics"] = {{"tangential", false}, {"rotation", true}};
  EXPECT_TRUE(Mentions(ErrorOf(json), "physics.rotation"));
}

TEST(SceneJson, TwoDimensionalScenesNeedABoxAndAWindow) {
  auto json = Minimal();
  json["dimension"] = 2;
  EXPECT_TRUE(Mentions(ErrorOf(json), "container.type"));
  json["container"] = {{"type", "box"}, {"min_m", {0, 0}}, {"max_m", {0.002, 0.002}}};
  json["insertion"]["region"] = {{"type", "box"}, {"min_m", {0, 0}}, {"max_m", {0.002, 0.002}}};
  EXPECT_TRUE(Mentions(ErrorOf(json), "measurement.window"));
  json["measurement"] = {{"window", {{"min_m", {0.0002, 0.0002}}, {"max_m", {0.0018, 0.0011}}}}};
  EXPECT_EQ(ErrorOf(json), "");
}

TEST(SceneJson, SpeciesFractionsMustSumToOne) {
  auto json = Minimal();
  json["particles"]["species"] = {{{"density_kg_per_m3", 7860}, {"volume_fraction", 0.3}},
                                  {{"density_kg_per_m3", 8920}, {"volume_fraction", 0.6}}};
  EXPECT_TRUE(Mentions(ErrorOf(json), "volume fractions sum to 0.9"));
}

TEST(SceneJson, MissingFileIsAnInputError) {
  EXPECT_THROW(LoadScene("/nonexistent/scene.json"), InputError);
}

TEST(SceneJson, MaterialCardSuppliesTheContactLaw) {
  const auto dir = std::filesystem::temp_directory_path() / "bouncecal_scene_json_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream card(dir / "steel.json");
    card << R"({"format": "bouncecal-material/1",
               "contact_law": {"law": "walton-braun",
                               "parameters": {"stiffness_n_per_m": 2e7, "gamma_n": 0.41}}})";
  }
  auto json = Minimal();
  json["material"] = {{"material_card", "steel.json"}};
  const Scene scene = SceneFromJson(json, dir / "scene.json");
  EXPECT_DOUBLE_EQ(scene.material.law.Get("gamma_n"), 0.41);
  EXPECT_DOUBLE_EQ(scene.material.law.Get("stiffness_n_per_m"), 2e7);
  json["material"]["contact_law"] = {{"law", "walton-braun"}};
  EXPECT_TRUE(Mentions(ErrorOf(json), "exactly one"));
  std::filesystem::remove_all(dir);
}

TEST(SceneJson, ShippedSampleScenesAllLoad) {
  const std::filesystem::path dir = std::filesystem::path(BOUNCECAL_SOURCE_DIR) / "samples/scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(LoadScene(entry.path())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 1);
}

}  // namespace
}  // namespace bouncecal::dem
