#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "bouncecal/dem/scene.h"
#include "bouncecal/dem/scene_templates.h"
#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::dem {
namespace {

using bouncecal::testing::ScratchPath;

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
std::string ErrorOf(const nlohmann::json& json,
                    const std::filesystem::path& source = "scene.json") {
  try {
    SceneFromJson(json, source);
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

TEST(SceneJson, LocalDampingScopeDefaultsToTheWholeForceAndNamesBadValues) {
  EXPECT_EQ(SceneFromJson(Minimal(), "scene.json").material.local_damping_scope,
            LocalDampingScope::kUnbalancedForce);
  auto json = Minimal();
  json["material"]["local_damping_scope"] = "contact-forces";
  EXPECT_EQ(SceneFromJson(json, "scene.json").material.local_damping_scope,
            LocalDampingScope::kContactForces);
  json["material"]["local_damping_scope"] = "unbalanced-force";
  EXPECT_EQ(SceneFromJson(json, "scene.json").material.local_damping_scope,
            LocalDampingScope::kUnbalancedForce);
  json["material"]["local_damping_scope"] = "contacts";
  const auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "material.local_damping_scope")) << message;
  EXPECT_TRUE(Mentions(message, "contact-forces")) << message;  // lists the valid values
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

// Writing a scene by hand: every missing and unknown key in one error, not one per run.
TEST(SceneJson, EveryMissingAndUnknownKeyIsNamedInOneError) {
  auto json = Minimal();
  json["particles"].erase("count");
  json["container"].erase("radius_m");
  json.erase("time_step_s");
  auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "scene.json: missing keys particles.count, container.radius_m, "
                       "time_step_s"))
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  // Missing keys in several parts, a misspelt one (unknown and missing at once) and a whole
  // missing part: each named once; the keys of a missing part are not listed one by one.
  json = Minimal();
  json["insertion"]["region"].erase("z_max_m");
  json["material"]["frictoin"] = 0.3;
  json["container"]["radius"] = json["container"]["radius_m"];
  json["container"].erase("radius_m");
  json.erase("measurement");
  message = ErrorOf(json);
  for (const char* named : {"container.radius_m", "insertion.region.z_max_m", "measurement",
                            "'container.radius'", "'material.frictoin'"}) {
    EXPECT_TRUE(Mentions(message, named)) << named << " in " << message;
  }
  EXPECT_FALSE(Mentions(message, "measurement.band_m")) << message;
  EXPECT_TRUE(Mentions(message, "5 problems")) << message;

  // A wrong value and a missing key in different parts: both, in one error.
  json = Minimal();
  json["time_step_s"] = "fast";
  json["particles"]["species"][0].erase("density_kg_per_m3");
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "particles.species[0].density_kg_per_m3: is missing")) << message;
  EXPECT_TRUE(Mentions(message, "time_step_s: must be a number")) << message;
}

// A check between values is not made on the stand-in of a missing key: no invented problem.
TEST(SceneJson, MissingKeysInventNoOtherProblems) {
  auto json = Minimal();
  json["container"].erase("radius_m");  // the region's check against the radius cannot be made
  EXPECT_EQ(ErrorOf(json), "scene.json: container.radius_m: is missing");
  json = Minimal();
  json["insertion"]["region"].erase("z_min_m");  // z_max_m >= z_min_m cannot be checked
  EXPECT_EQ(ErrorOf(json), "scene.json: insertion.region.z_min_m: is missing");
  json = Minimal();
  json["particles"]["species"] = {{{"density_kg_per_m3", 7800}}, {{"density_kg_per_m3", 2500}}};
  json["particles"]["species"][0]["volume_fraction"] = 0.5;  // the second's fraction is missing
  EXPECT_EQ(ErrorOf(json), "scene.json: particles.species[1].volume_fraction: is missing");
}

// Keys starting with '_' are comments (the scene templates use "_comment").
TEST(SceneJson, UnderscoreKeysAreComments) {
  auto json = Minimal();
  json["_comment"] = "a note";
  json["particles"]["_comment"] = {"notes", "in lines"};
  json["particles"]["species"][0]["_why"] = 1;
  EXPECT_EQ(ErrorOf(json), "");
}

// `bouncecal pack --template NAME`: each template is a complete scene, and each part of it says
// what its keys mean in a "_comment" (whether it also runs without a warning about its own set-up
// is checked through the command, tests/pack_cli_test.cc).
TEST(SceneJson, TemplatesLoadAndCommentEveryPart) {
  ASSERT_GE(SceneTemplates().size(), 2u);
  for (const auto& scene_template : SceneTemplates()) {
    const auto json = nlohmann::json::parse(scene_template.text);
    EXPECT_EQ(ErrorOf(json), "") << scene_template.name;
    EXPECT_TRUE(json.contains("_comment")) << scene_template.name;
    for (const char* part :
         {"particles", "container", "insertion", "material", "physics", "measurement", "outputs"}) {
      EXPECT_TRUE(json[part].contains("_comment")) << scene_template.name << " " << part;
    }
    EXPECT_EQ(FindSceneTemplate(scene_template.name)->text, scene_template.text);
  }
  EXPECT_EQ(
      SceneFromJson(nlohmann::json::parse(FindSceneTemplate("2d-box")->text), "t.json").dimension,
      2);
  EXPECT_FALSE(FindSceneTemplate("4d-hypercube").has_value());
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
  const auto dir = ScratchPath("test");
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
}

TEST(SceneJson, InsertionRegionMustLieInsideTheCylinder) {
  // Minimal(): a cylinder R = 0.1 m from z = 0; particles d = 1 cm.
  auto json = Minimal();
  json["insertion"]["region"]["radius_m"] = 0.2;
  auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "scene.json: insertion.region.radius_m: the region reaches 0.2 m "
                       "from the container's axis"))
      << message;
  EXPECT_TRUE(Mentions(message, "cylinder's radius 0.1 m")) << message;
  // Inside by radius alone, but off the axis.
  json = Minimal();
  json["insertion"]["region"]["center_m"] = {0.05, 0};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "insertion.region.radius_m: the region reaches 0.14 m")) << message;
  EXPECT_TRUE(Mentions(message, "centre offset 0.05 m + radius 0.09 m")) << message;
  json = Minimal();
  json["insertion"]["region"]["z_min_m"] = -0.05;
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "insertion.region.z_min_m: the region starts at z = -0.05 m, below "
                       "the container's floor at z = 0 m"))
      << message;
  // A floor away from the origin moves the limit with it.
  json = Minimal();
  json["container"]["center_m"] = {1, 2, 3};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "insertion.region.radius_m")) << message;
  json["insertion"]["region"]["center_m"] = {1, 2};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "insertion.region.z_min_m")) << message;
  // A box region's furthest corner counts, and the key is the one that places it.
  json = Minimal();
  json["insertion"]["region"] = {
      {"type", "box"}, {"min_m", {-0.08, -0.08, 0}}, {"max_m", {0.05, 0.05, 0.1}}};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "insertion.region.min_m: the region's corner (x, y) = (-0.08, "
                       "-0.08) m lies 0.113137085 m from the container's axis"))
      << message;
  json["insertion"]["region"] = {
      {"type", "box"}, {"min_m", {-0.07, -0.07, 0}}, {"max_m", {0.07, 0.07, 0.1}}};
  EXPECT_EQ(ErrorOf(json), "");
}

TEST(SceneJson, InsertionRegionMayStandAboveAnOpenContainerOnly) {
  // Paper 000 pours from 0.2-0.3 m into a cylinder 0.2 m high, whose rim is not modelled.
  auto json = Minimal();
  json["insertion"] = {
      {"type", "pour"},
      {"batch_interval_s", 0.1},
      {"region", {{"type", "cylinder"}, {"radius_m", 0.095}, {"z_min_m", 0.2}, {"z_max_m", 0.3}}}};
  EXPECT_EQ(ErrorOf(json), "");
  json["insertion"]["type"] = "random";
  json["insertion"].erase("batch_interval_s");
  EXPECT_EQ(ErrorOf(json), "");
  // A pour region as wide as the footprint is still checked above the rim.
  json["insertion"]["region"]["radius_m"] = 0.2;
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.region.radius_m"));
  // A box: sides always, the lid when closed.
  json = Minimal();
  json["container"] = {{"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {0.06, 0.06, 0.1}}};
  json["insertion"]["region"] = {
      {"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {0.06, 0.06, 0.2}}};
  EXPECT_EQ(ErrorOf(json), "");
  json["container"]["closed_top"] = true;
  auto message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "insertion.region.max_m: the region reaches z = 0.2 m, above the "
                       "container's closed top at z = 0.1 m"))
      << message;
  json["insertion"]["region"]["max_m"] = {0.2, 0.06, 0.1};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message,
                       "insertion.region.max_m: the region reaches x = 0.2 m, beyond the "
                       "container's side wall at x = 0.06 m"))
      << message;
  json["insertion"]["region"]["max_m"] = {0.06, 0.06, 0.1};
  json["insertion"]["region"]["min_m"] = {0, -0.01, 0};
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.region.min_m: the region reaches y = -0.01 m"));
  json["insertion"]["region"]["min_m"] = {0, 0, -0.01};
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.region.min_m: the region starts at z = -0.01 m"));
  // A cylinder region in a box: its circle must fit between the side walls.
  json["insertion"]["region"] = {{"type", "cylinder"},
                                 {"center_m", {0.03, 0.03}},
                                 {"radius_m", 0.04},
                                 {"z_min_m", 0},
                                 {"z_max_m", 0.1}};
  message = ErrorOf(json);
  EXPECT_TRUE(Mentions(message, "insertion.region.radius_m: the region reaches x = -0.01 m"))
      << message;
}

TEST(SceneJson, InsertionRegionOf2dScenesAndPlanes) {
  auto json = Minimal();
  json["dimension"] = 2;
  json["container"] = {
      {"type", "box"}, {"min_m", {0, 0}}, {"max_m", {0.002, 0.002}}, {"closed_top", true}};
  json["particles"]["diameter_m"] = 1e-4;
  json["measurement"] = {{"window", {{"min_m", {0, 0}}, {"max_m", {0.002, 0.001}}}}};
  // Paper 004's region is the box itself: particles are placed wholly inside the region.
  json["insertion"]["region"] = {{"type", "box"}, {"min_m", {0, 0}}, {"max_m", {0.002, 0.002}}};
  EXPECT_EQ(ErrorOf(json), "");
  json["insertion"]["region"]["max_m"] = {0.002, 0.003};
  EXPECT_TRUE(Mentions(ErrorOf(json), "insertion.region.max_m: the region reaches y = 0.003 m"));
  json = Minimal();
  json["container"] = {{"type", "plane"}, {"point_m", {0, 0, 0.05}}, {"normal", {0, 0, 2}}};
  EXPECT_EQ(ErrorOf(json), "");  // the region starts at z = 0.1
  json["container"]["point_m"] = {0, 0, 0.15};
  EXPECT_TRUE(
      Mentions(ErrorOf(json), "insertion.region.z_min_m: the region reaches 0.05 m behind"));
}

TEST(SceneJson, ADirectoryIsRefusedAsSceneFileOrMaterialCard) {
  const auto dir = ScratchPath("dir_test");
  std::filesystem::create_directories(dir / "card.json");
  try {
    LoadScene(dir);
    ADD_FAILURE() << "a directory loaded as a scene";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              dir.string() + ": is a directory, not a scene file; give the file's path");
  }
  auto json = Minimal();
  json["material"] = {{"material_card", "card.json"}};
  try {
    SceneFromJson(json, dir / "scene.json");
    ADD_FAILURE() << "a directory loaded as a material card";
  } catch (const InputError& error) {
    EXPECT_TRUE(Mentions(error.what(), "card.json: is a directory, not a material card"))
        << error.what();
  }
}

TEST(SceneJson, StartPositionsFileIsCheckedWhenTheSceneLoads) {
  const auto dir = ScratchPath("file_test");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "start.csv") << "x_m,y_m,z_m,diameter_m\n0,0,0.005,0.01\n0.2,0,0.005,0.01\n";
  auto json = Minimal();
  json["particles"]["count"] = 2;
  json["insertion"] = {{"type", "file"}, {"path", "start.csv"}};
  const auto message = ErrorOf(json, dir / "scene.json");
  EXPECT_TRUE(Mentions(message, "start.csv:3: particle at (0.2, 0, 0.005) lies outside"))
      << message;
  std::ofstream(dir / "start.csv") << "x_m,y_m,z_m,diameter_m\n0,0,0.005,0.01\n0.02,0,0.005,0.01\n";
  EXPECT_EQ(ErrorOf(json, dir / "scene.json"), "");
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
