#include "bouncecal/export/scene_packing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// The paper's pour (samples/scenes/paper000_cylinder_pour.json), moved off the origin to check
// that the adapter shifts everything to a floor centre at the origin.
nlohmann::json PaperPour() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "name": "pour",
    "dimension": 3,
    "particles": {"count": 2000, "diameter_m": 0.01,
                  "species": [{"name": "steel", "density_kg_per_m3": 7800, "volume_fraction": 1}]},
    "container": {"type": "cylinder", "center_m": [1, 2, 0.5], "radius_m": 0.1, "height_m": 0.2},
    "insertion": {"type": "pour",
                  "region": {"type": "cylinder", "center_m": [1, 2], "radius_m": 0.095,
                             "z_min_m": 0.7, "z_max_m": 0.8},
                  "batch_interval_s": 0.1, "seed": 1},
    "material": {"contact_law": {"law": "walton-braun",
                                 "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
                 "tangential_stiffness_n_per_m": 1e7, "friction": 0.3, "wall_friction": 0.3},
    "physics": {"tangential": true, "rotation": true, "van_der_waals": false,
                "local_damping": false},
    "time_step_s": 1e-5, "duration_s": 3, "gravity_mps2": 9.8,
    "measurement": {"band_m": [0.505, 0.545]},
    "outputs": {"directory": "out", "snapshot_interval_s": 0.5}
  })");
}

TEST(PackingDeckSpecFromScene, PaperPourKeepsEveryFigureRelativeToTheFloorCentre) {
  const auto spec = PackingDeckSpecFromScene(dem::SceneFromJson(PaperPour(), "pour.json"));
  EXPECT_EQ(spec.particle_count, 2000);
  EXPECT_EQ(spec.diameter_m, 0.01);
  EXPECT_FALSE(spec.max_diameter_m.has_value());
  EXPECT_EQ(spec.container, PackingContainer::kCylinder);
  EXPECT_EQ(spec.container_radius_m, 0.1);
  EXPECT_EQ(spec.insert_radius_m, 0.095);
  EXPECT_NEAR(spec.insert_z_min_m, 0.2, 1e-12);  // 0.7 m above a floor at 0.5 m
  EXPECT_NEAR(spec.insert_z_max_m, 0.3, 1e-12);
  EXPECT_EQ(spec.batch_interval_s, 0.1);
  EXPECT_EQ(spec.friction, 0.3);
  EXPECT_EQ(spec.gravity_mps2, 9.8);
  EXPECT_EQ(spec.snapshot_interval_s, 0.5);
}

// The deck starts where `bouncecal pack` does: the first batch its engine places at t = 0, every
// centre a radius inside the region (0.2-0.3 m over the floor, r < 0.095 m), shifted to a floor
// centre at the origin; a batch takes fewer than all 2000 here, so the rest are poured.
TEST(PackingDeckSpecFromScene, APourStartsFromTheFirstBatchBouncecalPlaces) {
  const auto spec = PackingDeckSpecFromScene(dem::SceneFromJson(PaperPour(), "pour.json"));
  ASSERT_FALSE(spec.start_spheres.empty());
  EXPECT_LE(spec.start_spheres.size(), 2000u);
  for (const auto& sphere : spec.start_spheres) {
    EXPECT_EQ(sphere.diameter_m, 0.01);
    EXPECT_LE(std::hypot(sphere.x_m, sphere.y_m), 0.095 - 0.005 + 1e-12);
    EXPECT_GE(sphere.z_m, 0.2 + 0.005 - 1e-12);
    EXPECT_LE(sphere.z_m, 0.3 - 0.005 + 1e-12);
  }
  // The same seed places the same spheres.
  const auto again = PackingDeckSpecFromScene(dem::SceneFromJson(PaperPour(), "pour.json"));
  ASSERT_EQ(again.start_spheres.size(), spec.start_spheres.size());
  EXPECT_EQ(again.start_spheres.back().x_m, spec.start_spheres.back().x_m);
}

TEST(PackingDeckSpecFromScene, ARandomStartIsReadWhole) {
  auto json = PaperPour();
  json["particles"]["count"] = 200;
  json["insertion"]["type"] = "random";
  json["insertion"].erase("batch_interval_s");
  const auto spec = PackingDeckSpecFromScene(dem::SceneFromJson(json, "pour.json"));
  EXPECT_EQ(spec.start_spheres.size(), 200u);
}

TEST(PackingDeckSpecFromScene, UniformDiametersBecomeARange) {
  auto json = PaperPour();
  json["particles"].erase("diameter_m");
  json["particles"]["diameter"] = {{"distribution", "uniform"}, {"min_m", 0.008}, {"max_m", 0.012}};
  const auto spec = PackingDeckSpecFromScene(dem::SceneFromJson(json, "pour.json"));
  EXPECT_EQ(spec.diameter_m, 0.008);
  EXPECT_EQ(spec.max_diameter_m, 0.012);
}

TEST(PackingDeckSpecFromScene, WhatTheDecksCannotExpressIsAConfigErrorNamingTheKey) {
  auto json = PaperPour();
  json["physics"]["van_der_waals"] = true;
  try {
    PackingDeckSpecFromScene(dem::SceneFromJson(json, "pour.json"));
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("pour.json: physics.van_der_waals"), std::string::npos)
        << error.what();
  }
  json = PaperPour();
  json["physics"]["stop_at_first_contact"] = true;
  EXPECT_THROW(PackingDeckSpecFromScene(dem::SceneFromJson(json, "pour.json")), ConfigError);
  json = PaperPour();
  // Off the axis but still inside the cylinder (0.003 + 0.095 < 0.1 m): a valid scene that the
  // decks' coaxial pour region cannot express.
  json["insertion"]["region"]["center_m"] = {1.003, 2};
  EXPECT_THROW(PackingDeckSpecFromScene(dem::SceneFromJson(json, "pour.json")), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
