#include "engine/energy_budget.h"

#include <gtest/gtest.h>

#include "engine/walls.h"

namespace bouncecal::dem::scene {
namespace {

Scene CylinderScene(bool van_der_waals) {
  Scene scene;
  scene.dimension = 3;
  scene.gravity_mps2 = 9.81;
  scene.container.kind = ContainerKind::kCylinder;
  scene.container.center_m = {0, 0, 0};
  scene.container.radius_m = 0.05;
  scene.container.height_m = 0.04;
  scene.particles.diameter.diameter_m = 0.01;
  scene.material.law.kind = ContactLawKind::kWaltonBraun;
  scene.material.law.parameters = {{"stiffness_n_per_m", 1e6}, {"gamma_n", 0.4}};
  scene.physics.tangential = false;
  scene.physics.rotation = false;
  scene.physics.van_der_waals = van_der_waals;
  return scene;
}

TEST(EnergyBudget, AddsLaunchHeightAndTheElasticEnergyOfStartOverlaps) {
  const Scene scene = CylinderScene(false);
  EngineSettings settings;
  settings.gravity_mps2 = scene.gravity_mps2;
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  auto engine =
      MakeEngine<3>(settings, ContainerWalls<3>(scene.container), scene.material.law, physics);
  const double r = 0.005;
  const double overlap = 1e-4;        // between the first two spheres
  const double floor_overlap = 2e-4;  // of the third sphere with the floor
  engine->AddParticle(Vec<3>{{0, 0, 0.02}}, Vec<3>{{0.3, 0, 0}}, r, 7800, 0);
  engine->AddParticle(Vec<3>{{2 * r - overlap, 0, 0.02}}, Vec<3>{{0, 0, 0}}, r, 7800, 0);
  engine->AddParticle(Vec<3>{{0, 0.03, r - floor_overlap}}, Vec<3>{{0, 0, 0}}, r, 7800, 0);
  const double m = SphereMassKg(7800, r);
  // Walton-Braun unloads along (1 - gamma) k: that is what an overlap can give back.
  auto elastic = [](double xi) { return 0.5 * 1e6 * (1 - 0.4) * xi * xi; };
  const double expected = 0.5 * m * 0.3 * 0.3 + m * 9.81 * (0.02 + 0.02 + r - floor_overlap) +
                          elastic(overlap) + elastic(floor_overlap);
  EnergyBudget budget(scene, *engine, 3);
  ASSERT_TRUE(budget.bounded());
  // Sums of a few terms: rounding only.
  EXPECT_NEAR(budget.joules(), expected, 1e-12 * expected);
  // A poured sphere brings its height and launch speed.
  engine->AddParticle(Vec<3>{{-0.03, 0, 0.1}}, Vec<3>{{0, 0, -1}}, r, 7800, 0);
  budget.AddInserted(*engine, 3);
  const double poured = m * 9.81 * 0.1 + 0.5 * m * 1.0;
  EXPECT_NEAR(budget.joules(), expected + poured, 1e-12 * (expected + poured));
}

TEST(EnergyBudget, VanDerWaalsAllowanceAndUnboundedTiltedPlane) {
  Scene scene = CylinderScene(true);
  EngineSettings settings;
  PhysicsSpec physics;
  auto engine =
      MakeEngine<3>(settings, ContainerWalls<3>(scene.container), scene.material.law, physics);
  // No particle yet: only the allowance for 10 to come, 6 pairs each releasing at most
  // A R_eff / (6 h_min) with R_eff = r / 2.
  const EnergyBudget budget(scene, *engine, 10);
  const double per_pair = scene.material.hamaker_j * 0.0025 / (6 * scene.material.vdw_min_gap_m);
  EXPECT_NEAR(budget.joules(), 60 * per_pair, 1e-12 * 60 * per_pair);
  // On a tilted plane a sphere can slide below any height: no budget applies.
  scene.container.kind = ContainerKind::kPlane;
  scene.container.normal = {0.1, 0, 1};
  EXPECT_FALSE(EnergyBudget(scene, *engine, 10).bounded());
}

}  // namespace
}  // namespace bouncecal::dem::scene
