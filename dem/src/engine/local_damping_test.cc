// The scope of Cundall's local damping (material.local_damping_scope): on the whole unbalanced
// force, gravity included (Itasca PFC), or on the forces from other bodies only. Checked against
// the closed forms of a free fall, a particle resting on a floor and one sliding on it.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/engine.h"

namespace bouncecal::dem::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAlpha = 0.7;
constexpr double kRadiusM = 50e-6;  // paper 004's disks
constexpr double kDensity = 7860;
constexpr double kStiffness = 100;  // N/m, the paper-004 scenes' spring
constexpr double kG = 9.81;
constexpr double kDt = 1e-6;

double Mass() { return kDensity * 4.0 / 3.0 * kPi * kRadiusM * kRadiusM * kRadiusM; }

Vec<2> V2(double x, double y) { return Vec<2>{{x, y}}; }

ContactLawConfig ElasticLinearLaw() {
  ContactLawConfig law;
  law.kind = ContactLawKind::kLinearDashpot;
  law.parameters = {{"stiffness_n_per_m", kStiffness}, {"damping_ratio", 0.0}};
  return law;
}

std::vector<Wall<2>> Floor() {
  Wall<2> floor;
  floor.point = V2(0, 0);
  floor.normal = V2(0, 1);
  return {floor};
}

EngineSettings Settings(LocalDampingScope scope) {
  EngineSettings settings;
  settings.time_step_s = kDt;
  settings.gravity_mps2 = kG;
  settings.local_damping = kAlpha;
  settings.local_damping_scope = scope;
  settings.tangential_stiffness_n_per_m = kStiffness;
  settings.friction = 0.364;
  settings.wall_friction = 0.364;
  return settings;
}

// Sliding needs the tangential force; rotation is left out so the particle slides and does not
// roll (the closed form below is for sliding).
PhysicsSpec DampedPhysics(bool tangential) {
  PhysicsSpec physics;
  physics.tangential = tangential;
  physics.rotation = false;
  physics.local_damping = true;
  return physics;
}

// Free flight meets no other body, so the contact-only scope has nothing to damp: the fall is
// g exactly. The whole-force scope scales gravity by (1 - alpha) while it drives the fall. The
// force is constant, so velocity Verlet is exact and only rounding remains (1e-9 relative).
TEST(LocalDampingScope, FreeFallIsExactlyGUnderContactScopeAndDampedUnderTheWholeForce) {
  const double v0 = -0.01;  // already falling, so the damping sign is set from the first step
  const std::int64_t steps = 20000;
  const double t = steps * kDt;
  for (const auto scope :
       {LocalDampingScope::kContactForces, LocalDampingScope::kUnbalancedForce}) {
    auto engine = MakeEngine<2>(Settings(scope), {}, ElasticLinearLaw(), DampedPhysics(false));
    engine->AddParticle(V2(0, 0), V2(0, v0), kRadiusM, kDensity, 0);
    engine->Advance(steps);
    const double a = scope == LocalDampingScope::kContactForces ? kG : (1 - kAlpha) * kG;
    const auto& s = engine->state();
    EXPECT_NEAR(s.velocity_mps[0][1], v0 - a * t, 1e-9 * a * t);
    EXPECT_NEAR(s.position_m[0][1], v0 * t - 0.5 * a * t * t, 1e-9 * 0.5 * a * t * t);
    EXPECT_EQ(s.velocity_mps[0][0], 0.0);
  }
}

// A particle placed at its equilibrium overlap m g / k on a floor, at rest. Under the whole-force
// scope the unbalanced force is zero up to rounding, so nothing moves: the speed stays below the
// rounding of one step's kick (1e-12 of g dt). Under the contact-only scope the damping acts on
// the floor's push m g as soon as rounding leaves any velocity, a Coulomb-like force alpha m g
// against the motion. It cannot make energy, so the particle stays at rest to within the kick it
// gives in one step: speed below alpha g dt and a centre within alpha g dt^2 per step of where
// it started, bounded overall by the dead zone alpha m g / k of a spring with Coulomb friction.
TEST(LocalDampingScope, AParticleRestingOnAFloorStaysAtRestUnderBothScopes) {
  const double overlap_m = Mass() * kG / kStiffness;
  for (const auto scope :
       {LocalDampingScope::kContactForces, LocalDampingScope::kUnbalancedForce}) {
    auto engine = MakeEngine<2>(Settings(scope), Floor(), ElasticLinearLaw(), DampedPhysics(false));
    const double y0 = kRadiusM - overlap_m;
    engine->AddParticle(V2(0, y0), V2(0, 0), kRadiusM, kDensity, 0);
    double max_speed = 0, max_shift = 0;
    for (int k = 0; k < 200; ++k) {  // 20 ms in all
      engine->Advance(100);
      const auto& s = engine->state();
      max_speed = std::max(max_speed, std::hypot(s.velocity_mps[0][0], s.velocity_mps[0][1]));
      max_shift = std::max(max_shift, std::abs(s.position_m[0][1] - y0));
    }
    const double omega = std::sqrt(kStiffness / Mass());
    if (scope == LocalDampingScope::kUnbalancedForce) {
      // The equilibrium overlap is only known to the rounding of the position (one ulp of y0,
      // 7e-21 m); an error of a few ulps makes an oscillation of speed omega * ulp (1e-15 m/s).
      const double ulp = std::nextafter(y0, 1.0) - y0;
      EXPECT_LT(max_speed, 100 * omega * ulp);
    } else {
      EXPECT_LE(max_speed, kAlpha * kG * kDt * (1 + 1e-9));
      EXPECT_LE(max_shift, kAlpha * overlap_m);
    }
    // Undamped, the same particle released from its touching height (overlap 0) would oscillate
    // about the equilibrium with amplitude m g / k and speed up to g / omega: the bounds above
    // (alpha times the amplitude; alpha omega dt = 0.11 times the speed) separate the two.
    EXPECT_LT(kAlpha * kG * kDt, 0.2 * kG / omega);
  }
}

// A particle resting on a floor and sliding along it: the floor's friction mu m g opposes the
// motion, so under either scope the damping scales it by (1 + alpha) (the horizontal force has no
// gravity in it) and the particle decelerates at (1 + alpha) mu g until it stops. The whole-force
// scope leaves the normal force at m g exactly; under the contact-only scope the normal force
// jitters by up to alpha m g from step to step (see the resting test), and so does the friction
// cap, but only within its Coulomb dead zone: 2 % covers what it averages to over the slide.
TEST(LocalDampingScope, ASlidingParticleDeceleratesAtOnePlusAlphaMuG) {
  const double mu = 0.364;
  const double v0 = 0.01;
  const double expected = (1 + kAlpha) * mu * kG;
  const double stop_s = v0 / expected;  // 1.65 ms
  for (const auto scope :
       {LocalDampingScope::kContactForces, LocalDampingScope::kUnbalancedForce}) {
    auto engine = MakeEngine<2>(Settings(scope), Floor(), ElasticLinearLaw(), DampedPhysics(true));
    engine->AddParticle(V2(0, kRadiusM - Mass() * kG / kStiffness), V2(v0, 0), kRadiusM, kDensity,
                        0);
    // The spring saturates at the Coulomb cap within one step; measure over the middle of the
    // slide, away from the start and the stop.
    const auto quarter = static_cast<std::int64_t>(0.25 * stop_s / kDt);
    engine->Advance(quarter);
    const double v1 = engine->state().velocity_mps[0][0];
    engine->Advance(2 * quarter);
    const double v2 = engine->state().velocity_mps[0][0];
    const double tolerance = scope == LocalDampingScope::kContactForces ? 0.02 : 1e-6;
    EXPECT_NEAR((v1 - v2) / (2 * quarter * kDt) / expected, 1.0, tolerance);
    engine->Advance(4 * quarter);  // well past the stop
    // Stopped: what is left is the jitter of a tangential spring below its cap.
    EXPECT_LT(std::abs(engine->state().velocity_mps[0][0]), 1e-3 * v0);
  }
}

}  // namespace
}  // namespace bouncecal::dem::scene
