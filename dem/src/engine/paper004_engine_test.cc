// The two integration rules of paper 004 (Cheng, Guo & Lai 1999): the locally damped
// central-difference update (its eq. 12) and the velocity set to zero at a particle's first
// collision (its sections 2 and 3.1).

#include <gtest/gtest.h>

#include <cmath>

#include "engine/engine.h"

namespace bouncecal::dem::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

ContactLawConfig ElasticLinearLaw(double stiffness_n_per_m) {
  ContactLawConfig law;
  law.kind = ContactLawKind::kLinearDashpot;
  law.parameters = {{"stiffness_n_per_m", stiffness_n_per_m}, {"damping_ratio", 0.0}};
  return law;
}

PhysicsSpec NormalOnly() {
  PhysicsSpec physics;
  physics.tangential = false;
  physics.rotation = false;
  return physics;
}

Vec<2> V2(double x, double y) { return Vec<2>{{x, y}}; }

std::vector<Wall<2>> Floor() {
  Wall<2> floor;
  floor.point = V2(0, 0);
  floor.normal = V2(0, 1);
  return {floor};
}

// Eq. 12: v(t + dt/2) = v(t - dt/2) + (1 -+ alpha) F/m dt, the force scaled by (1 - alpha) when it
// drives the motion and by (1 + alpha) when it opposes it (Cundall 1987; Itasca PFC). Under
// gravity alone a falling particle therefore accelerates at (1 - alpha) g and a rising one
// decelerates at (1 + alpha) g. The force is constant over each phase, so the central difference
// is exact there and only rounding remains: 1e-9 relative.
TEST(Paper004Integration, LocalDampingScalesTheForceByOneMinusOrPlusAlpha) {
  EngineSettings settings;
  settings.time_step_s = 1e-5;
  settings.gravity_mps2 = 9.81;
  settings.local_damping = 0.7;
  PhysicsSpec physics = NormalOnly();
  physics.local_damping = true;
  const double g = settings.gravity_mps2;
  const double dt = settings.time_step_s;

  auto falling = MakeEngine<2>(settings, {}, ElasticLinearLaw(100), physics);
  falling->AddParticle(V2(0, 0), V2(0, -0.01), 50e-6, 7860, 0);
  falling->Advance(100);
  const double v1 = falling->state().velocity_mps[0][1];
  falling->Advance(1000);
  const double v2 = falling->state().velocity_mps[0][1];
  EXPECT_NEAR((v2 - v1) / (1000 * dt), -(1 - 0.7) * g, 1e-9 * g);

  auto rising = MakeEngine<2>(settings, {}, ElasticLinearLaw(100), physics);
  rising->AddParticle(V2(0, 0), V2(0, 1.0), 50e-6, 7860, 0);
  rising->Advance(100);
  const double u1 = rising->state().velocity_mps[0][1];
  rising->Advance(1000);  // 0.01 s: still rising (1 m/s takes 0.06 s to stop at 1.7 g)
  const double u2 = rising->state().velocity_mps[0][1];
  ASSERT_GT(u2, 0);
  EXPECT_NEAR((u2 - u1) / (1000 * dt), -(1 + 0.7) * g, 1e-9 * g);
}

struct Landing {
  double rebound_m = 0;        // highest centre after the first contact, above the touching height
  double horizontal_mps = 0;   // largest |v_x| after the first contact
  std::int64_t untouched = 0;  // particles that never touched anything
};

// A disk dropped with a horizontal velocity onto a frictionless elastic floor: without damping
// it bounces back to its drop height and keeps sliding.
Landing DropOnFloor(bool stop_at_first_contact, double drop_m, double dt) {
  EngineSettings settings;
  settings.time_step_s = dt;
  settings.stop_at_first_contact = stop_at_first_contact;
  const double r = 50e-6;
  auto engine = MakeEngine<2>(settings, Floor(), ElasticLinearLaw(100), NormalOnly());
  engine->AddParticle(V2(0, r + drop_m), V2(0.05, 0), r, 7860, 0);
  Landing landing;
  bool landed = false;
  const double fall_s = std::sqrt(2 * drop_m / settings.gravity_mps2);
  const auto steps = static_cast<std::int64_t>(3 * fall_s / dt);  // fall, bounce, fall again
  for (std::int64_t step = 0; step < steps; ++step) {
    engine->Advance(1);
    const auto& s = engine->state();
    landed = landed || s.position_m[0][1] < r;
    if (landed) {
      landing.rebound_m = std::max(landing.rebound_m, s.position_m[0][1] - r);
      landing.horizontal_mps = std::max(landing.horizontal_mps, std::abs(s.velocity_mps[0][0]));
    }
  }
  EXPECT_TRUE(landed);
  landing.untouched = engine->untouched();
  return landing;
}

TEST(Paper004Integration, FirstContactStopsAFallingParticleThatWouldOtherwiseBounce) {
  const double drop_m = 1e-4;
  const double dt = 1e-6;  // contact time pi sqrt(m/k) = 20 us: 20 steps per contact
  const Landing elastic = DropOnFloor(false, drop_m, dt);
  // The elastic bounce returns to the drop height up to the integration error: 0.9 is loose.
  EXPECT_GT(elastic.rebound_m, 0.9 * drop_m);
  EXPECT_NEAR(elastic.horizontal_mps, 0.05, 1e-12);

  const Landing stopped = DropOnFloor(true, drop_m, dt);
  EXPECT_EQ(stopped.untouched, 0);
  // The whole velocity is zeroed, and a frictionless floor never gives it back along x.
  EXPECT_EQ(stopped.horizontal_mps, 0.0);
  // What is left after the stop is the spring energy of the overlap reached in the step that
  // crossed the floor, at most 1/2 k (v dt)^2 with v the impact speed: it can lift the particle
  // by at most that over m g.
  const double r = 50e-6;
  const double mass = 7860 * 4.0 / 3.0 * kPi * r * r * r;
  const double impact_mps = std::sqrt(2 * 9.81 * drop_m);
  const double bound_m = 0.5 * 100 * std::pow(impact_mps * dt, 2) / (mass * 9.81);
  EXPECT_LT(stopped.rebound_m, bound_m);
  EXPECT_LT(bound_m, 0.05 * drop_m);  // so the check above separates the two behaviours
}

// Two particles meeting head-on in free space are both stopped: neither had touched anything.
// Each stop happens once, so the overlap spring then pushes them apart slowly, with at most the
// spring energy of the overlap reached in the meeting step, 1/2 k (v_rel dt)^2.
TEST(Paper004Integration, FirstContactStopsBothParticlesOfAPair) {
  EngineSettings settings;
  settings.time_step_s = 1e-7;
  settings.gravity_mps2 = 0;
  settings.stop_at_first_contact = true;
  const double r = 50e-6;
  const double v = 0.1;
  auto engine = MakeEngine<2>(settings, {}, ElasticLinearLaw(100), NormalOnly());
  engine->AddParticle(V2(0, 0), V2(v, 0), r, 7860, 0);
  engine->AddParticle(V2(2 * r + 1e-6, 0), V2(-v, 0), r, 7860, 0);
  EXPECT_EQ(engine->untouched(), 2);
  engine->Advance(100);  // they meet after 5e-6 s = 50 steps; the spring acts for 20 us more
  EXPECT_EQ(engine->untouched(), 0);
  engine->Advance(400);
  const auto& s = engine->state();
  const double mass = 7860 * 4.0 / 3.0 * kPi * r * r * r;
  const double spring_j = 0.5 * 100 * std::pow(2 * v * settings.time_step_s, 2);
  // Both share it (each gets half). The central difference conserves energy only up to
  // O((omega dt)^2) = 5e-4 with omega = sqrt(k / m_eff) = 2.2e5 1/s: a 1 % margin covers it.
  const double max_speed = 1.01 * std::sqrt(spring_j / mass);
  const double speed = std::max(std::abs(s.velocity_mps[0][0]), std::abs(s.velocity_mps[1][0]));
  EXPECT_LE(speed, max_speed);
  EXPECT_LT(max_speed, 0.05 * v);  // against a full elastic rebound at v
  EXPECT_EQ(s.velocity_mps[0][1], 0.0);
}

}  // namespace
}  // namespace bouncecal::dem::scene
