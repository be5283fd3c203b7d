#include "engine/engine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <variant>

#include "scene/insertion.h"

namespace bouncecal::dem::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

ContactLawConfig WaltonBraunLaw(double stiffness, double gamma) {
  ContactLawConfig law;
  law.kind = ContactLawKind::kWaltonBraun;
  law.parameters = {{"stiffness_n_per_m", stiffness}, {"gamma_n", gamma}};
  return law;
}

// A law with a normal history (the plastic overlap each pair carries between steps).
ContactLawConfig WaltonBraunPlasticLaw() {
  ContactLawConfig law;
  law.kind = ContactLawKind::kWaltonBraunPlastic;
  law.parameters = {{"stiffness_n_per_m", 1e6},
                    {"unloading_stiffness_n_per_m", 3e6},
                    {"plastic_flow_overlap_m", 0.0}};
  return law;
}

PhysicsSpec AllPhysics(bool vdw) {
  PhysicsSpec physics;
  physics.tangential = true;
  physics.rotation = true;
  physics.van_der_waals = vdw;
  physics.local_damping = false;
  return physics;
}

std::vector<Wall<3>> BoxWalls(double size) {
  ContainerSpec box;
  box.kind = ContainerKind::kBox;
  box.min_m = {0, 0, 0};
  box.max_m = {size, size, size};
  box.closed_top = true;
  return ContainerWalls<3>(box);
}

ContainerSpec Cylinder(double radius_m, double height_m) {
  ContainerSpec cylinder;
  cylinder.kind = ContainerKind::kCylinder;
  cylinder.center_m = {0, 0, 0};
  cylinder.radius_m = radius_m;
  cylinder.height_m = height_m;
  return cylinder;
}

Vec<3> V3(double x, double y, double z) { return Vec<3>{{x, y, z}}; }

// A dense, overlapping random cloud with random velocities and spins: every contact branch
// (loading, unloading, sliding, sticking, walls) is exercised.
void FillRandomCloud(EngineBase<3>& engine, int n, double size, double radius, std::uint64_t seed) {
  SceneRandom random(seed);
  for (int k = 0; k < n; ++k) {
    const double r = radius * random.Uniform(0.8, 1.2);
    engine.AddParticle(
        V3(random.Uniform(r, size - r), random.Uniform(r, size - r), random.Uniform(r, size - r)),
        V3(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)), r, 7800, 0);
  }
  auto& s = engine.mutable_state();
  for (auto& w : s.angular_velocity_radps) {
    w = V3(random.Uniform(-50, 50), random.Uniform(-50, 50), random.Uniform(-50, 50));
  }
}

EngineSettings Settings(bool brute_force, int threads, bool sort_by_cell = true) {
  EngineSettings settings;
  settings.sort_by_cell = sort_by_cell;
  settings.time_step_s = 1e-6;
  settings.gravity_mps2 = 9.81;
  settings.tangential_stiffness_n_per_m = 5e6;
  settings.friction = 0.3;
  settings.wall_friction = 0.4;
  settings.vdw_cutoff_gap_m = 2e-4;
  settings.skin_m = 1e-3;
  settings.brute_force_pairs = brute_force;
  settings.threads = threads;
  return settings;
}

// 300 random disks with paper 004's physics (van der Waals, rotation, local damping), run for
// 300 steps by an engine with each of the two settings: the trajectories must match bit for bit.
void ExpectSameDiskTrajectories(const EngineSettings& a_settings, const EngineSettings& b_settings,
                                std::uint64_t seed, const std::string& what) {
  PhysicsSpec disks = AllPhysics(true);
  disks.local_damping = true;
  auto a = MakeEngine<2>(a_settings, {}, WaltonBraunLaw(1e6, 0.4), disks);
  auto b = MakeEngine<2>(b_settings, {}, WaltonBraunLaw(1e6, 0.4), disks);
  SceneRandom random(seed);
  for (int k = 0; k < 300; ++k) {
    const Vec<2> x{{random.Uniform(0, 0.1), random.Uniform(0, 0.1)}};
    const Vec<2> v{{random.Uniform(-1, 1), random.Uniform(-1, 1)}};
    const double r = 0.0035 * random.Uniform(0.8, 1.2);
    a->AddParticle(x, v, r, 7800, 0);
    b->AddParticle(x, v, r, 7800, 0);
  }
  a->Advance(300);
  b->Advance(300);
  for (std::int32_t i = 0; i < a->state().size(); ++i) {
    ASSERT_TRUE(a->state().position_m[i] == b->state().position_m[i]) << what << " " << i;
    ASSERT_TRUE(a->state().velocity_mps[i] == b->state().velocity_mps[i]) << what << " " << i;
  }
  // The disks really collided: otherwise equal states would prove nothing.
  ASSERT_GT(a->pairs().size(), 300u) << what;
}

// Advances both engines `rounds` times by `steps` and requires bit-identical positions after
// each: the grid engine must not miss a contact the brute-force one sees.
void ExpectSameTrajectories(EngineBase<3>& grid, EngineBase<3>& brute, int rounds, int steps) {
  for (int round = 0; round < rounds; ++round) {
    grid.Advance(steps);
    brute.Advance(steps);
    for (std::int32_t i = 0; i < grid.state().size(); ++i) {
      ASSERT_TRUE(grid.state().position_m[i] == brute.state().position_m[i])
          << "particle " << i << " round " << round;
    }
  }
}

TEST(PackingEngine, TwoParticleForcesObeyNewtonsThirdLaw) {
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e7, 0.5), AllPhysics(false));
  engine->AddParticle(V3(0, 0, 0), V3(0.3, -0.1, 0.2), 0.005, 7800, 0);
  engine->AddParticle(V3(0.0089, 0.0005, 0.0003), V3(-0.2, 0.4, 0.1), 0.004, 7800, 0);
  engine->mutable_state().angular_velocity_radps[0] = V3(10, -20, 5);
  engine->mutable_state().angular_velocity_radps[1] = V3(-3, 7, 40);
  for (int call = 0; call < 5; ++call) {  // let the tangential spring build up
    engine->ComputeForces();
    const auto& s = engine->state();
    // Exact: the pair force is computed once and added with opposite signs.
    for (int d = 0; d < 3; ++d) EXPECT_EQ(s.force_n[0][d], -s.force_n[1][d]);
    EXPECT_GT(s.force_n[0].norm(), 0);
    // Torque about each centre from the same tangential force at the contact: t_i / r_i equals
    // t_j / r_j (both are -(n x F_t)); rounding only.
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(s.torque_nm[0][d] / 0.005, s.torque_nm[1][d] / 0.004, 1e-12);
    }
  }
}

TEST(PackingEngine, TouchingParticlesWithoutOverlapFeelNoForce) {
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e7, 0.5), AllPhysics(false));
  engine->AddParticle(V3(0, 0, 0), V3(1, 0, 0), 0.25, 7800, 0);
  engine->AddParticle(V3(0.5, 0, 0), V3(-1, 0, 0), 0.25, 7800, 0);  // exactly touching
  engine->ComputeForces();
  EXPECT_EQ(engine->state().force_n[0].norm(), 0.0);
  EXPECT_EQ(engine->state().force_n[1].norm(), 0.0);
}

// The distance pass clears a pair's record only when it stops interacting (engine.h,
// pair_live_): after a glancing collision the pair must hold no spring and no force, and a
// second collision must run exactly as the same collision in a fresh engine.
TEST(PackingEngine, SeparatedPairForgetsItsSpringAndCollidesAgainLikeAFreshPair) {
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e7, 0.5), AllPhysics(false));
  engine->AddParticle(V3(0, 0, 0), V3(0.5, 0, 0), 0.005, 7800, 0);
  engine->AddParticle(V3(0.0102, 0.004, 0), V3(-0.5, 0, 0), 0.005, 7800, 0);
  const auto distance = [&] {
    return (engine->state().position_m[0] - engine->state().position_m[1]).norm();
  };
  bool touched = false;
  int steps = 0;
  for (; steps < 20000 && !(touched && distance() > 0.0101); ++steps) {
    engine->Advance(1);
    touched = touched || engine->PairShear(0).norm() > 0;
  }
  ASSERT_TRUE(touched) << "the spheres never built a tangential spring";
  ASSERT_LT(steps, 20000) << "the spheres did not separate";
  EXPECT_TRUE(engine->PairShear(0) == Vec<3>::Zero());
  for (int k = 0; k < 2; ++k) EXPECT_TRUE(engine->state().force_n[k] == Vec<3>::Zero());
  // Send them back into each other, once in this engine and once in a fresh one.
  auto fresh = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e7, 0.5), AllPhysics(false));
  for (int k = 0; k < 2; ++k) {
    const auto& s = engine->state();
    fresh->AddParticle(s.position_m[k], -1.0 * s.velocity_mps[k], s.radius_m[k], 7800, 0);
    fresh->mutable_state().angular_velocity_radps[k] = s.angular_velocity_radps[k];
  }
  for (int k = 0; k < 2; ++k) {
    engine->mutable_state().velocity_mps[k] = fresh->state().velocity_mps[k];
  }
  fresh->Advance(2 * steps);
  engine->Advance(2 * steps);
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(engine->state().position_m[k] == fresh->state().position_m[k]) << k;
    EXPECT_TRUE(engine->state().velocity_mps[k] == fresh->state().velocity_mps[k]) << k;
  }
}

TEST(PackingEngine, CellGridAndBruteForceGiveIdenticalForcesAndTrajectories) {
  for (bool vdw : {false, true}) {
    // Unsorted: the cell order would sum each particle's forces in another order.
    auto grid = MakeEngine<3>(Settings(false, 1, false), BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4),
                              AllPhysics(vdw));
    auto brute =
        MakeEngine<3>(Settings(true, 1), BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4), AllPhysics(vdw));
    FillRandomCloud(*grid, 200, 0.05, 0.0035, 3);
    FillRandomCloud(*brute, 200, 0.05, 0.0035, 3);
    grid->ComputeForces();
    brute->ComputeForces();
    ASSERT_LT(grid->pairs().size(), brute->pairs().size() / 5);  // the grid really prunes
    std::size_t touching = 0;
    for (std::size_t p = 0; p < grid->pairs().size(); ++p)
      touching += grid->PairShear(p).norm() > 0;
    EXPECT_GT(touching, 50u);  // a dense cloud with many contacts
    // Many steps with rebuilds: the contacting pairs are summed in the same order, so the
    // results agree bit for bit (zero forces of far pairs add exactly nothing).
    for (int round = 0; round < 4; ++round) {
      const auto& a = grid->state();
      const auto& b = brute->state();
      for (std::int32_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(a.force_n[i] == b.force_n[i]) << "particle " << i << " round " << round;
        ASSERT_TRUE(a.torque_nm[i] == b.torque_nm[i]) << "particle " << i;
        ASSERT_TRUE(a.position_m[i] == b.position_m[i]) << "particle " << i;
      }
      grid->Advance(150);
      brute->Advance(150);
    }
    EXPECT_GT(grid->rebuilds(), 1);
  }
}

TEST(PackingEngine, AdaptiveSkinMissesNoContactAndNarrowsAsParticlesSlowDown) {
  // The skin is chosen again at every rebuild; the rebuild rule (any particle moved half of the
  // current skin) must keep every contact listed, so the trajectories match the brute-force
  // engine bit for bit, as with a fixed skin.
  EngineSettings adaptive = Settings(false, 1, false);
  adaptive.skin_m = 1e-3;
  adaptive.min_skin_m = 5e-5;
  adaptive.skin_rebuild_steps = 20;
  auto grid = MakeEngine<3>(adaptive, BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4), AllPhysics(true));
  auto brute =
      MakeEngine<3>(Settings(true, 1), BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4), AllPhysics(true));
  FillRandomCloud(*grid, 200, 0.05, 0.0035, 7);
  FillRandomCloud(*brute, 200, 0.05, 0.0035, 7);
  grid->Advance(1);
  brute->Advance(1);
  // Up to ~1.7 m/s: 2 v dt steps = 2 * 1.7 * 1e-6 * 20 = 6.8e-5 m, between the bounds.
  EXPECT_GT(grid->skin_m(), adaptive.min_skin_m);
  EXPECT_LT(grid->skin_m(), adaptive.skin_m);
  ExpectSameTrajectories(*grid, *brute, 4, 300);
  EXPECT_GT(grid->rebuilds(), 10);
  // At rest the narrowest skin is taken.
  auto resting =
      MakeEngine<3>(adaptive, BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4), AllPhysics(false));
  resting->AddParticle(V3(0.01, 0.01, 0.01), V3(0, 0, 0), 0.003, 7800, 0);
  resting->ComputeForces();
  EXPECT_EQ(resting->skin_m(), adaptive.min_skin_m);
  // Fast, the widest.
  auto fast = MakeEngine<3>(adaptive, BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4), AllPhysics(false));
  fast->AddParticle(V3(0.01, 0.01, 0.01), V3(100, 0, 0), 0.003, 7800, 0);
  fast->ComputeForces();
  EXPECT_EQ(fast->skin_m(), adaptive.skin_m);
}

TEST(PackingEngine, CellOrderOnlyChangesTheLastBitsAndKeepsTheCallersOrder) {
  // The engine reorders particles by cell at every rebuild and carries each pair's history
  // across (negated when its members swap): a lost or mis-signed spring would change a force
  // at the first order, a wrong permutation would move particles to other indices.
  auto sorted = MakeEngine<3>(Settings(false, 1, true), BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4),
                              AllPhysics(true));
  auto plain = MakeEngine<3>(Settings(false, 1, false), BoxWalls(0.05), WaltonBraunLaw(1e6, 0.4),
                             AllPhysics(true));
  FillRandomCloud(*sorted, 200, 0.05, 0.0035, 3);
  FillRandomCloud(*plain, 200, 0.05, 0.0035, 3);
  const std::vector<double> radius_added = sorted->state().radius_m;
  for (int round = 0; round < 4; ++round) {
    sorted->Advance(150);
    plain->Advance(150);
    const auto& a = sorted->state();
    const auto& b = plain->state();
    ASSERT_EQ(a.radius_m, radius_added);  // every particle is where the caller put it
    for (std::int32_t i = 0; i < a.size(); ++i) {
      // Only the order of each particle's force sum differs (a few ulp of the force), and 600
      // steps of this dense cloud amplify that to far below 1e-9 of a force; a missing or
      // reversed spring (k_t x, x ~ v dt steps ~ 1e-6 m) would change forces at the 1e-1 level.
      const double scale = std::max(1.0, b.force_n[i].norm());
      ASSERT_LT((a.force_n[i] - b.force_n[i]).norm(), 1e-9 * scale)
          << "particle " << i << " round " << round;
      ASSERT_LT((a.position_m[i] - b.position_m[i]).norm(), 1e-12) << "particle " << i;
    }
  }
  EXPECT_GT(sorted->rebuilds(), 1);
}

TEST(PackingEngine, CylinderWallsAreNeverMissedByTheWallNeighbourList) {
  // Particles flung at the floor and the side of a cylinder: the grid engine checks a wall only
  // for particles within the skin of it at the last rebuild, the brute-force engine checks every
  // wall every step. Any contact the list missed would change the trajectories.
  const ContainerSpec cylinder = Cylinder(0.03, 0.04);
  const auto law = WaltonBraunLaw(1e6, 0.4);
  auto grid =
      MakeEngine<3>(Settings(false, 1, false), ContainerWalls<3>(cylinder), law, AllPhysics(false));
  auto brute =
      MakeEngine<3>(Settings(true, 1), ContainerWalls<3>(cylinder), law, AllPhysics(false));
  SceneRandom random(11);
  for (int k = 0; k < 120; ++k) {
    const double angle = random.Uniform(0, 2 * kPi);
    const double rho = random.Uniform(0, 0.025);
    const Vec<3> x = V3(rho * std::cos(angle), rho * std::sin(angle), random.Uniform(0.004, 0.06));
    // Outward and downward at up to 3 m/s: many side and floor impacts, some above the rim.
    const Vec<3> v = V3(3 * std::cos(angle), 3 * std::sin(angle), random.Uniform(-3, 1));
    grid->AddParticle(x, v, 0.003, 7800, 0);
    brute->AddParticle(x, v, 0.003, 7800, 0);
  }
  ExpectSameTrajectories(*grid, *brute, 5, 400);
  EXPECT_GT(grid->rebuilds(), 5);
}

// The side wall is a thin shell of finite height: touched from inside, from outside, or over
// its rim. A sphere outside it used to be read as overlapping the inner face by more than its
// diameter and was flung in (energy from nothing).
TEST(PackingEngine, CylinderShellPushesOutsideSpheresOutAndRoundsItsRim) {
  const ContainerSpec cylinder = Cylinder(0.05, 0.04);
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  const double k = 1e6;
  const double r = 0.005;
  const double overlap = 1e-4;
  auto force_on = [&](const Vec<3>& x) {
    auto engine =
        MakeEngine<3>(settings, ContainerWalls<3>(cylinder), WaltonBraunLaw(k, 0.0), physics);
    engine->AddParticle(x, V3(0, 0, 0), r, 7800, 0);
    engine->ComputeForces();
    return engine->state().force_n[0];
  };
  // Outside, below the rim, touching the outer face: pushed out by k xi (gamma 0, at rest).
  const Vec<3> outside = force_on(V3(0.05 + r - overlap, 0, 0.02));
  EXPECT_NEAR(outside[0], k * overlap, 1e-9 * k * overlap);
  EXPECT_EQ(outside[1], 0);
  EXPECT_EQ(outside[2], 0);
  // Outside and clear of the shell: no force.
  EXPECT_EQ(force_on(V3(0.05 + r + 1e-4, 0, 0.02)).norm(), 0);
  // Inside, touching the inner face: pushed in, as before.
  EXPECT_NEAR(force_on(V3(0.05 - r + overlap, 0, 0.02))[0], -k * overlap, 1e-9 * k * overlap);
  // Straight above the rim edge: pushed up, by the overlap with the edge.
  const Vec<3> above = force_on(V3(0.05, 0, 0.04 + r - overlap));
  EXPECT_NEAR(above[2], k * overlap, 1e-9 * k * overlap);
  EXPECT_NEAR(above[0], 0, 1e-12);
  // Diagonally over the edge (45 degrees, outside): along the diagonal, same magnitude.
  const double diagonal = (r - overlap) / std::sqrt(2.0);
  const Vec<3> corner = force_on(V3(0.05 + diagonal, 0, 0.04 + diagonal));
  EXPECT_NEAR(corner[0], k * overlap / std::sqrt(2.0), 1e-6 * k * overlap);
  EXPECT_NEAR(corner[2], k * overlap / std::sqrt(2.0), 1e-6 * k * overlap);
}

TEST(PackingEngine, SphereDroppedOnTheRimOrBesideTheCylinderGainsNoEnergy) {
  // Elastic law, no friction: whatever the sphere hits (the rim's edge, the outer face, the
  // floor outside), its kinetic plus potential energy must not grow. The old inner-face formula
  // turned 1 m/s into ~24 m/s here.
  const ContainerSpec cylinder = Cylinder(0.05, 0.04);
  EngineSettings settings = Settings(false, 1);
  settings.time_step_s = 1e-6;
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  const double r = 0.005;
  for (const double x0 : {0.05, 0.05 + 0.5 * r, 0.05 + 1.5 * r, 0.05 - 0.5 * r}) {
    auto engine =
        MakeEngine<3>(settings, ContainerWalls<3>(cylinder), WaltonBraunLaw(1e6, 0.0), physics);
    engine->AddParticle(V3(x0, 0, 0.06), V3(0, 0, 0), r, 7800, 0);
    const double mass = engine->state().mass_kg[0];
    auto energy = [&] {
      return engine->KineticEnergyJ() +
             mass * settings.gravity_mps2 * engine->state().position_m[0][2];
    };
    const double e0 = energy();
    for (int chunk = 0; chunk < 40; ++chunk) {
      engine->Advance(5000);  // 0.2 s in all: falls 2 cm, hits, bounces
      // Velocity Verlet's energy error at ~100 steps per contact is below 1e-3 of the drop
      // energy per impact; 1 % leaves room for a few impacts.
      ASSERT_LT(energy(), e0 * 1.01 + 1e-12) << "x0 " << x0 << " chunk " << chunk;
    }
  }
}

TEST(PackingEngine, TangentialSpringGrowsLinearlyThenIsCappedByCoulomb) {
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  settings.time_step_s = 1e-6;
  settings.tangential_stiffness_n_per_m = 1e6;
  settings.friction = 0.3;
  PhysicsSpec physics = AllPhysics(false);
  physics.rotation = false;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e7, 0.0), physics);
  const double overlap = 1e-5;
  engine->AddParticle(V3(0, 0, 0), V3(0, 0, 0), 0.005, 7800, 0);
  engine->AddParticle(V3(0.01 - overlap, 0, 0), V3(0, 0.1, 0), 0.005, 7800, 0);
  const double normal = 1e7 * overlap;  // gamma 0 and no normal motion: k xi
  for (int call = 1; call <= 200; ++call) {
    engine->ComputeForces();  // each call advances the spring by v_t dt (positions fixed)
    const auto& f = engine->state().force_n[1];
    const double tangential = std::abs(f[1]);
    const double spring = 1e6 * 0.1 * 1e-6 * call;
    // Rounding only; the cap must hold exactly (up to one ulp of the rescaling).
    EXPECT_NEAR(tangential, std::min(spring, 0.3 * normal), 1e-12);
    EXPECT_LE(tangential, 0.3 * normal * (1 + 1e-15));
    EXPECT_LT(f[1], 0);  // opposes the sliding of particle 1
    EXPECT_NEAR(f[0], normal, 1e-9);
  }
}

// A sphere meeting the floor and the cylinder side head-on, without gravity: a wall is a body
// of infinite mass, so the law's closed forms hold with m_eff = m (a pair of equal spheres would
// last sqrt(2) times shorter). 1e-7 s steps put ~700 steps in a contact; Verlet's error on this
// law is then ~1e-5 in e (docs/drop_accuracy.md), so 1e-3 is a safe bound, and the duration is
// read to the step.
TEST(PackingEngine, WallImpactsKeepTheLawsRestitutionAndDurationWithTheSphereMass) {
  EngineSettings settings = Settings(false, 1);
  settings.gravity_mps2 = 0;
  settings.time_step_s = 1e-7;
  // Walton-braun's e does not depend on the mass; the linear dashpot's damping does (through
  // m_eff), so its e would move if a wall were taken for a sphere.
  ContactLawConfig dashpot;
  dashpot.kind = ContactLawKind::kLinearDashpot;
  dashpot.parameters = {{"stiffness_n_per_m", 1e7}, {"damping_ratio", 0.2}};
  const double r = 0.005;
  const double m = SphereMassKg(7800, r);
  struct Case {
    const char* wall;
    Vec<3> start;
    Vec<3> velocity;
    int axis;  // the component along the wall's normal
  };
  const Case cases[] = {{"floor", V3(0, 0, r + 1e-4), V3(0, 0, -1), 2},
                        {"cylinder side", V3(0.1 - r - 1e-4, 0, 0.1), V3(1, 0, 0), 0}};
  for (const ContactLawConfig& law_config : {WaltonBraunLaw(1e7, 0.5), dashpot}) {
    double e = 0;
    double duration = 0;
    std::visit(
        [&](const auto& law) {
          e = *law.ClosedFormRestitution(m, r, 1.0);
          duration = *law.ClosedFormContactDuration(m, r, 1.0);
        },
        MakeContactLaw(law_config));
    for (const auto& c : cases) {
      auto engine = MakeEngine<3>(settings, ContainerWalls<3>(Cylinder(0.1, 0.2)), law_config,
                                  AllPhysics(false));
      engine->AddParticle(c.start, c.velocity, r, 7800, 0);
      const double approach = c.velocity[c.axis];
      int steps_in_contact = 0;
      for (int step = 0; step < 4000; ++step) {
        engine->Advance(1);
        const double x = engine->state().position_m[0][c.axis];
        const double gap = c.axis == 2 ? x - r : (0.1 - r) - x;
        if (gap < 0) ++steps_in_contact;
      }
      const std::string what = std::string(ToString(law_config.kind)) + " on the " + c.wall;
      const double rebound = engine->state().velocity_mps[0][c.axis];
      EXPECT_NEAR(-rebound / approach, e, 1e-3) << what;
      EXPECT_NEAR(steps_in_contact * settings.time_step_s, duration, 2 * settings.time_step_s)
          << what;
      // Head-on: no tangential force, no spin.
      EXPECT_EQ(engine->state().angular_velocity_radps[0].squaredNorm(), 0.0) << what;
    }
  }
}

// A sphere launched sliding along the floor without spin: wall friction slows it and spins it up
// until it rolls, after t = 2 v0 / (7 mu g), at v = 5/7 v0 with omega r = v (solid sphere,
// I = 2/5 m r^2). Tests the wall's friction, torque and its sign. The sphere starts at its
// resting overlap m g / k; the tangential spring, undamped once it sticks, rings with an
// amplitude mu g / omega_t ~ 2e-4 m/s, so speeds are held to 2e-3 of v0 and the time to the step
// where slipping ends to 2 %.
TEST(PackingEngine, SphereSlidingOnTheFloorEndsRollingAtFiveSeventhsOfItsSpeed) {
  EngineSettings settings = Settings(false, 1);
  settings.time_step_s = 2e-6;
  settings.wall_friction = 0.4;
  const double k = 1e7;
  const double r = 0.005;
  const double m = SphereMassKg(7800, r);
  auto engine = MakeEngine<3>(settings, ContainerWalls<3>(Cylinder(0.1, 0.2)),
                              WaltonBraunLaw(k, 0.5), AllPhysics(false));
  const double v0 = 1;
  engine->AddParticle(V3(-0.05, 0, r - m * settings.gravity_mps2 / k), V3(v0, 0, 0), r, 7800, 0);
  const double expected_roll_s = 2 * v0 / (7 * settings.wall_friction * settings.gravity_mps2);
  double rolled_at_s = -1;
  for (int step = 0; step < 60000; ++step) {
    engine->Advance(1);
    const auto& s = engine->state();
    const double slip = s.velocity_mps[0][0] - r * s.angular_velocity_radps[0][1];
    if (rolled_at_s < 0 && slip < 0.01 * v0) rolled_at_s = engine->time_s();
  }
  const auto& s = engine->state();
  EXPECT_NEAR(rolled_at_s, expected_roll_s, 0.02 * expected_roll_s);
  EXPECT_NEAR(s.velocity_mps[0][0], 5.0 / 7.0 * v0, 2e-3 * v0);
  EXPECT_NEAR(r * s.angular_velocity_radps[0][1], 5.0 / 7.0 * v0, 2e-3 * v0);
  EXPECT_NEAR(s.velocity_mps[0][1], 0, 1e-9);
}

TEST(PackingEngine, ElasticFrictionlessGasConservesEnergy) {
  EngineSettings settings = Settings(false, 1);
  settings.gravity_mps2 = 0;
  settings.time_step_s = 2e-6;  // ~60 steps per contact (t_c = pi sqrt(m/2k) = 1.2e-4 s)
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  auto engine = MakeEngine<3>(settings, BoxWalls(0.05), WaltonBraunLaw(1e6, 0.0), physics);
  SceneRandom random(5);
  std::vector<NewParticle> none;
  Scene scene;
  scene.insertion.kind = InsertionKind::kRandom;
  scene.insertion.region.min_m = {0, 0, 0};
  scene.insertion.region.max_m = {0.05, 0.05, 0.05};
  std::vector<NewParticle> pending(150);
  for (auto& p : pending) p.radius_m = 0.0035;
  for (const auto& p : PlaceInRegion(scene, pending, none, random)) {
    engine->AddParticle(V3(p.position_m[0], p.position_m[1], p.position_m[2]),
                        V3(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)),
                        p.radius_m, 7800, 0);
  }
  ASSERT_EQ(engine->state().size(), 150);
  const double e0 = engine->KineticEnergyJ();
  engine->Advance(20000);  // 0.04 s: every particle crosses the box and collides many times
  const double e1 = engine->KineticEnergyJ();
  // Velocity Verlet on a piecewise-linear force errs by O((dt/t_c)^2) per contact at the onset
  // kink, with random sign; with ~60 steps per contact that stays far below 1% over the run.
  // The elastic energy held in the contacts open at the end (a few of 150 particles, each for
  // 1e-4 s of 0.04 s) is also below 1%: 2% bounds both.
  EXPECT_NEAR(e1 / e0, 1.0, 0.02);
}

TEST(PackingEngine, ResultsDoNotDependOnTheThreadCount) {
  // 1500 particles: enough pairs and particles that the pool really splits both loops.
  auto one =
      MakeEngine<3>(Settings(false, 1), BoxWalls(0.1), WaltonBraunLaw(1e6, 0.4), AllPhysics(true));
  auto two =
      MakeEngine<3>(Settings(false, 2), BoxWalls(0.1), WaltonBraunLaw(1e6, 0.4), AllPhysics(true));
  FillRandomCloud(*one, 1500, 0.1, 0.0035, 9);
  FillRandomCloud(*two, 1500, 0.1, 0.0035, 9);
  one->Advance(100);
  two->Advance(100);
  ASSERT_GT(two->pairs().size(), 2048u);
  for (std::int32_t i = 0; i < one->state().size(); ++i) {
    ASSERT_TRUE(one->state().position_m[i] == two->state().position_m[i]) << i;
    ASSERT_TRUE(one->state().velocity_mps[i] == two->state().velocity_mps[i]) << i;
  }
}

// The builds of the contact arithmetic this CPU can run beyond the baseline.
std::vector<ContactSimd> WiderContactBuilds() {
  std::vector<ContactSimd> builds;
  for (ContactSimd simd : {ContactSimd::kAvx2, ContactSimd::kAvx512}) {
    if (simd <= CpuContactSimd()) builds.push_back(simd);
  }
  return builds;
}

const char* SimdName(ContactSimd simd) {
  switch (simd) {
    case ContactSimd::kAvx512:
      return "avx512";
    case ContactSimd::kAvx2:
      return "avx2";
    case ContactSimd::kBaseline:
      break;
  }
  return "baseline";
}

// Every law and physics combination the vectorised contact stages are built for, run with each
// wider build and with the baseline build on the same dense cloud: element-wise IEEE arithmetic
// in the same order must give the same bits (a contracted FMA or a reordered sum would not).
TEST(PackingEngine, WideAndBaselineContactArithmeticGiveIdenticalTrajectories) {
  const auto builds = WiderContactBuilds();
  if (builds.empty()) GTEST_SKIP() << "this CPU has no AVX2: only the baseline build can run";
  std::vector<ContactLawConfig> laws(5);
  laws[0] = WaltonBraunLaw(1e6, 0.4);
  laws[1] = WaltonBraunPlasticLaw();
  laws[2].kind = ContactLawKind::kLinearDashpot;
  laws[2].parameters = {{"stiffness_n_per_m", 1e6}, {"damping_ratio", 0.2}};
  laws[3].kind = ContactLawKind::kHertz;
  laws[3].parameters = {{"effective_modulus_pa", 1e9}};
  laws[4].kind = ContactLawKind::kHertzViscoelastic;
  laws[4].parameters = {{"effective_modulus_pa", 1e9}, {"dissipative_time_s", 2e-6}};
  PhysicsSpec normal_only;
  normal_only.tangential = false;
  normal_only.rotation = false;
  normal_only.van_der_waals = false;
  EngineSettings baseline_settings = Settings(false, 1);
  baseline_settings.max_contact_simd = ContactSimd::kBaseline;
  for (ContactSimd simd : builds) {
    EngineSettings wide_settings = Settings(false, 1);
    wide_settings.max_contact_simd = simd;
    for (const auto& law : laws) {
      for (const auto& physics : {AllPhysics(false), AllPhysics(true), normal_only}) {
        auto wide = MakeEngine<3>(wide_settings, BoxWalls(0.05), law, physics);
        auto baseline = MakeEngine<3>(baseline_settings, BoxWalls(0.05), law, physics);
        FillRandomCloud(*wide, 200, 0.05, 0.0035, 5);
        FillRandomCloud(*baseline, 200, 0.05, 0.0035, 5);
        wide->Advance(300);
        baseline->Advance(300);
        const auto& a = wide->state();
        const auto& b = baseline->state();
        for (std::int32_t i = 0; i < a.size(); ++i) {
          ASSERT_TRUE(a.position_m[i] == b.position_m[i])
              << SimdName(simd) << " " << ToString(law.kind) << " " << i;
          ASSERT_TRUE(a.velocity_mps[i] == b.velocity_mps[i])
              << SimdName(simd) << " " << ToString(law.kind) << " " << i;
          ASSERT_TRUE(a.angular_velocity_radps[i] == b.angular_velocity_radps[i])
              << SimdName(simd) << " " << i;
        }
        // The cloud really collided: otherwise equal states would prove nothing.
        ASSERT_GT(wide->pairs().size(), 200u);
      }
    }
    // 2D disks with van der Waals, rotation and local damping (paper 004's physics).
    ExpectSameDiskTrajectories(wide_settings, baseline_settings, 11, SimdName(simd));
  }
}

// The pair pass either runs every listed pair through the contact stages or compacts the
// interacting ones first (EngineSettings::dense_pair_fraction): the same arithmetic per pair, so
// the same bits, for every law (the history law included), with and without the van der Waals
// cutoff (which lists pairs that do not touch), in 3D and in 2D.
TEST(PackingEngine, DenseAndCompactedPairPassesGiveIdenticalTrajectories) {
  EngineSettings dense_settings = Settings(false, 2);
  dense_settings.dense_pair_fraction = 0;
  EngineSettings compacted_settings = Settings(false, 2);
  compacted_settings.dense_pair_fraction = 2;
  for (const ContactLawConfig& law : {WaltonBraunLaw(1e6, 0.4), WaltonBraunPlasticLaw()}) {
    for (bool vdw : {false, true}) {
      auto dense = MakeEngine<3>(dense_settings, BoxWalls(0.05), law, AllPhysics(vdw));
      auto compacted = MakeEngine<3>(compacted_settings, BoxWalls(0.05), law, AllPhysics(vdw));
      FillRandomCloud(*dense, 300, 0.05, 0.0035, 9);
      FillRandomCloud(*compacted, 300, 0.05, 0.0035, 9);
      for (int round = 0; round < 3; ++round) {
        dense->Advance(200);
        compacted->Advance(200);
        for (std::int32_t i = 0; i < dense->state().size(); ++i) {
          ASSERT_TRUE(dense->state().position_m[i] == compacted->state().position_m[i])
              << ToString(law.kind) << " vdw " << vdw << " particle " << i;
          ASSERT_TRUE(dense->state().angular_velocity_radps[i] ==
                      compacted->state().angular_velocity_radps[i])
              << ToString(law.kind) << " vdw " << vdw << " particle " << i;
        }
      }
      // Listed pairs that do not touch are what the two passes treat differently.
      std::size_t apart = 0;
      const auto& s = dense->state();
      for (std::size_t p = 0; p < dense->pairs().size(); ++p) {
        const auto i = dense->pairs().first[p];
        const auto j = dense->pairs().second[p];
        const double gap = std::sqrt((s.position_m[i] - s.position_m[j]).squaredNorm()) -
                           s.radius_m[i] - s.radius_m[j];
        if (gap > 0) ++apart;
      }
      EXPECT_GT(apart, 0u) << ToString(law.kind) << " vdw " << vdw;
    }
  }
  ExpectSameDiskTrajectories(dense_settings, compacted_settings, 13, "2D");
}

// Single-precision contacts (EngineSettings::single_precision_contacts) must still resolve the
// overlaps of a settled pack: about 4e-9 m per sphere weight in paper 000 (k = 1e7 N/m, 4.1 g),
// below float's spacing of 9.3e-10 m at a 1 cm centre distance, so r_i + r_j - |d| in float
// would be wrong by 10-100 %. Five separate pairs of 1 cm spheres at rest, overlapping by
// 1e-9 .. 1e-5 m (four through the four-wide gather, one through the scalar tail), no gravity:
// each sphere feels k delta along the line of centres. The expected force is exact in double
// (the centre distance and the overlap are differences of doubles within a factor of two of each
// other: Sterbenz), and the single path rounds four times on the way (the difference of squares,
// the sum and the quotient of the overlap, the force back to float), so within 4 float epsilons.
TEST(PackingEngine, SinglePrecisionContactsResolveOverlapsBelowFloatSpacingOfTheDistance) {
  const double stiffness = 1e7;
  EngineSettings settings = Settings(false, 1);
  settings.gravity_mps2 = 0;
  settings.dense_pair_fraction = 0;  // every step after the first runs the dense blocks
  settings.single_precision_contacts = true;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(stiffness, 0.5), AllPhysics(false));
  const double r = 0.005;
  const std::vector<double> overlaps = {1e-9, 1e-8, 1e-7, 1e-6, 1e-5};
  for (std::size_t p = 0; p < overlaps.size(); ++p) {
    const double y = 0.05 * static_cast<double>(p);
    engine->AddParticle(V3(0.02, y, 0.02), V3(0, 0, 0), r, 7800, 0);
    engine->AddParticle(V3(0.02 + 2 * r - overlaps[p], y, 0.02), V3(0, 0, 0), r, 7800, 0);
  }
  // The first pass runs the compacted (double) blocks: a chunk picks dense from its previous step.
  engine->ComputeForces();
  engine->ComputeForces();
  const auto& s = engine->state();
  for (std::size_t p = 0; p < overlaps.size(); ++p) {
    const auto i = static_cast<std::int32_t>(2 * p);
    const double overlap = 2 * r - (s.position_m[i + 1][0] - s.position_m[i][0]);
    const double expected = stiffness * overlap;
    const double tolerance = 4 * std::numeric_limits<float>::epsilon() * expected;
    EXPECT_NEAR(s.force_n[i][0], -expected, tolerance) << overlaps[p];
    EXPECT_NEAR(s.force_n[i + 1][0], expected, tolerance) << overlaps[p];
    EXPECT_EQ(s.force_n[i][1], 0.0);
    EXPECT_EQ(s.force_n[i][2], 0.0);
  }
}

// With single-precision contacts a chunk that runs its pairs compacted converts them into the
// same float arithmetic as a dense one, so that choice (which depends on how the pairs fall into
// chunks, hence on the thread count) and the build change no bit, as in double: dense blocks on
// two threads with the widest build against compacted blocks on one thread with the baseline
// build, for a law with and without a normal history, with and without the van der Waals cutoff.
TEST(PackingEngine, SinglePrecisionContactsAreTheSameForEveryPassThreadCountAndBuild) {
  EngineSettings dense_settings = Settings(false, 2);
  dense_settings.dense_pair_fraction = 0;
  dense_settings.single_precision_contacts = true;
  EngineSettings compacted_settings = Settings(false, 1);
  compacted_settings.dense_pair_fraction = 2;
  compacted_settings.single_precision_contacts = true;
  compacted_settings.max_contact_simd = ContactSimd::kBaseline;
  for (const ContactLawConfig& law : {WaltonBraunLaw(1e6, 0.4), WaltonBraunPlasticLaw()}) {
    for (bool vdw : {false, true}) {
      auto dense = MakeEngine<3>(dense_settings, BoxWalls(0.05), law, AllPhysics(vdw));
      auto compacted = MakeEngine<3>(compacted_settings, BoxWalls(0.05), law, AllPhysics(vdw));
      auto reference = MakeEngine<3>(Settings(false, 1), BoxWalls(0.05), law, AllPhysics(vdw));
      for (auto* engine : {dense.get(), compacted.get(), reference.get()}) {
        FillRandomCloud(*engine, 300, 0.05, 0.0035, 9);
        engine->Advance(600);
      }
      bool differs_from_double = false;
      for (std::int32_t i = 0; i < dense->state().size(); ++i) {
        ASSERT_TRUE(dense->state().position_m[i] == compacted->state().position_m[i])
            << ToString(law.kind) << " vdw " << vdw << " particle " << i;
        ASSERT_TRUE(dense->state().angular_velocity_radps[i] ==
                    compacted->state().angular_velocity_radps[i])
            << ToString(law.kind) << " vdw " << vdw << " particle " << i;
        differs_from_double |= !(dense->state().position_m[i] == reference->state().position_m[i]);
      }
      // The float arithmetic did run: the double engine took other bits.
      EXPECT_TRUE(differs_from_double) << ToString(law.kind) << " vdw " << vdw;
    }
  }
}

TEST(PackingEngine, VanDerWaalsAttractsNearbyParticlesWithTheHamakerForce) {
  EngineSettings settings = Settings(true, 1);
  settings.gravity_mps2 = 0;
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  physics.van_der_waals = true;
  auto engine = MakeEngine<3>(settings, {}, WaltonBraunLaw(1e3, 0.0), physics);
  const double r = 50e-6;
  const double gap = 5e-9;
  engine->AddParticle(V3(0, 0, 0), V3(0, 0, 0), r, 7860, 0);
  engine->AddParticle(V3(2 * r + gap, 0, 0), V3(0, 0, 0), r, 7860, 0);
  engine->ComputeForces();
  // Paper 004 eq. 2 for equal spheres: A R / (12 h^2), towards the other particle.
  const double expected = settings.hamaker_j * r / (12 * gap * gap);
  EXPECT_NEAR(engine->state().force_n[0][0], expected, 1e-9 * expected);
  EXPECT_NEAR(engine->state().force_n[1][0], -expected, 1e-9 * expected);
}

TEST(PairList, NonFinitePositionsGiveNoPairsInsteadOfHanging) {
  std::vector<Vec<3>> x = {V3(0, 0, 0), V3(0.001, 0, 0), V3(std::nan(""), 0, 0)};
  const std::vector<double> r = {0.001, 0.001, 0.001};
  EXPECT_EQ(GridPairs<3>(x, r, 0.0).size(), 0u);
  x[2] = V3(1e200, 0, 0);
  EXPECT_EQ(GridPairs<3>(x, r, 0.0).size(), 0u);
  x[2] = V3(0.5, 0, 0);
  EXPECT_EQ(GridPairs<3>(x, r, 0.0).size(), 1u);  // the touching pair (0, 1)
}

}  // namespace
}  // namespace bouncecal::dem::scene
