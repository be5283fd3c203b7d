#include "bouncecal/dem/drop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

constexpr std::array<Integrator, 3> kSteppedIntegrators = {
    Integrator::kVelocityVerlet, Integrator::kSymplecticEuler, Integrator::kRungeKutta4};

DropOptions PaperDrop(double gamma = 0.5) {
  DropOptions options;
  options.law = {.kind = ContactLawKind::kWaltonBraun,
                 .parameters = {{"stiffness_n_per_m", 1e7}, {"gamma_n", gamma}}};
  return options;
}

bool AllFinite(const DropResult& result) {
  for (const DropImpact& impact : result.impacts) {
    for (double value :
         {impact.time_s, impact.restitution, impact.energy_loss, impact.contact_duration_s,
          impact.max_overlap_m, impact.speed_in_mps, impact.speed_out_mps}) {
      if (!std::isfinite(value)) return false;
    }
  }
  for (const TrajectoryPoint& point : result.trajectory) {
    if (!std::isfinite(point.time_s + point.height_m + point.velocity_mps)) return false;
  }
  return std::isfinite(result.cpu_s) && std::isfinite(result.end_time_s);
}

TEST(SimulateDrop, DefaultOptionsAreValidAndDropToRest) {
  const DropResult result = SimulateDrop(DropOptions{});
  EXPECT_EQ(result.stop_reason, DropStopReason::kAtRest) << result.stop_detail;
  EXPECT_GE(result.impacts.size(), 15u);
  EXPECT_FALSE(result.stop_detail.empty());
  EXPECT_TRUE(AllFinite(result));
  EXPECT_GT(result.time_step_s, 0);
  EXPECT_LT(result.time_step_s, result.stability_limit_s);
}

// The first impact happens when the free fall from h0 ends: t = sqrt(2 h0 / g), v = sqrt(2 g h0),
// to rounding, for every integrator and both step grids (the onset is located, not stepped).
TEST(SimulateDrop, FirstImpactIsAtTheFreeFallTimeWhateverTheIntegrator) {
  for (Integrator integrator : {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler,
                                Integrator::kRungeKutta4, Integrator::kExact}) {
    for (bool grid : {false, true}) {
      DropOptions options = PaperDrop();
      options.integrator = integrator;
      options.fixed_step_grid = grid;
      options.max_impacts = 2;
      const DropResult result = SimulateDrop(options);
      ASSERT_FALSE(result.impacts.empty());
      EXPECT_NEAR(result.impacts[0].time_s, std::sqrt(2 * 0.2 / 9.81), 1e-12);
      EXPECT_NEAR(result.impacts[0].speed_in_mps, std::sqrt(2 * 9.81 * 0.2), 1e-12);
    }
  }
}

// Exact path: e_1 is the gravity-free closed form up to gravity acting during the contact, a
// relative effect of order g t_c / v_out (2.2e-3 at gamma 0.9, where the soft unloading branch
// is slow); tolerance 2 g t_c / v_out. Consecutive onsets are separated by the contact plus the
// ballistic flight 2 v_out / g, exactly.
TEST(SimulateDrop, ExactPathAgreesWithClosedFormAndBallistics) {
  for (double gamma : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    DropOptions options = PaperDrop(gamma);
    options.integrator = Integrator::kExact;
    const DropResult result = SimulateDrop(options);
    ASSERT_GE(result.impacts.size(), 3u);
    const double e = std::sqrt((1 - gamma) / (1 + gamma));
    const DropImpact& first = result.impacts[0];
    const double tolerance = 2 * 9.81 * first.contact_duration_s / first.speed_out_mps;
    EXPECT_NEAR(first.restitution, e, tolerance * e) << gamma;
    for (std::size_t k = 0; k + 1 < result.impacts.size(); ++k) {
      const DropImpact& impact = result.impacts[k];
      EXPECT_NEAR(result.impacts[k + 1].time_s - impact.time_s,
                  impact.contact_duration_s + 2 * impact.speed_out_mps / 9.81, 1e-12);
    }
  }
}

// Every stepped integrator at 1000 steps per contact against the exact path for all three
// linear laws: e_k and onset times of the first 5 impacts. With the turning point and the
// release located, the remaining error is the first-order Euler error O(dt / t_c) = 1e-3 on e;
// tolerance 2e-3. An error de on impact j shifts all later onsets by 2 de v_in,j / g, so the
// onset tolerance is the sum of those over the earlier impacts.
TEST(SimulateDrop, FineStepsConvergeToTheExactPathForLinearLaws) {
  for (ContactLawKind kind : {ContactLawKind::kWaltonBraun, ContactLawKind::kWaltonBraunPlastic,
                              ContactLawKind::kLinearDashpot}) {
    DropOptions options;
    options.law = {.kind = kind, .parameters = {}};
    options.max_impacts = 5;
    options.integrator = Integrator::kExact;
    const DropResult exact = SimulateDrop(options);
    for (Integrator integrator : kSteppedIntegrators) {
      options.integrator = integrator;
      options.steps_per_contact = 1000;
      const DropResult stepped = SimulateDrop(options);
      ASSERT_EQ(stepped.impacts.size(), exact.impacts.size()) << ToString(kind);
      double onset_tolerance = 1e-12;
      for (std::size_t k = 0; k < exact.impacts.size(); ++k) {
        EXPECT_NEAR(stepped.impacts[k].restitution, exact.impacts[k].restitution, 2e-3)
            << ToString(kind) << " " << ToString(integrator) << " impact " << k;
        EXPECT_NEAR(stepped.impacts[k].time_s, exact.impacts[k].time_s, onset_tolerance)
            << ToString(kind) << " " << ToString(integrator) << " impact " << k;
        onset_tolerance += 2 * 2e-3 * exact.impacts[k].speed_in_mps / 9.81;
      }
    }
  }
}

// Nonlinear laws: the coarse integrators approach RK4 at 1000 steps per contact, and Hertz
// keeps e = 1 (tolerance 1e-4: Verlet's energy error at 1000 steps is ~(pi/1000)^2).
TEST(SimulateDrop, HertzLawsConvergeToTheRungeKuttaReference) {
  for (ContactLawKind kind : {ContactLawKind::kHertz, ContactLawKind::kHertzViscoelastic}) {
    DropOptions options;
    options.law = {.kind = kind, .parameters = {}};
    options.max_impacts = 3;
    options.integrator = Integrator::kRungeKutta4;
    options.steps_per_contact = 1000;
    const DropResult reference = SimulateDrop(options);
    ASSERT_EQ(reference.impacts.size(), 3u);
    if (kind == ContactLawKind::kHertz) {
      EXPECT_NEAR(reference.impacts[0].restitution, 1, 1e-6);
    }
    for (Integrator integrator : {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler}) {
      options.integrator = integrator;
      const DropResult coarse = SimulateDrop(options);
      ASSERT_EQ(coarse.impacts.size(), 3u);
      EXPECT_NEAR(coarse.impacts[0].restitution, reference.impacts[0].restitution, 1e-4)
          << ToString(kind) << " " << ToString(integrator);
    }
  }
}

// Hertz contact duration from the drop against Johnson's closed form (gravity-free): the
// gravity correction is again ~ g t_c / v ~ 1e-4; tolerance 1e-3 relative.
TEST(SimulateDrop, HertzContactDurationMatchesClosedForm) {
  DropOptions options;
  options.law = {.kind = ContactLawKind::kHertz, .parameters = {}};
  options.integrator = Integrator::kRungeKutta4;
  options.steps_per_contact = 500;
  options.max_impacts = 1;
  const DropResult result = SimulateDrop(options);
  ASSERT_EQ(result.impacts.size(), 1u);
  const Hertz law({.effective_modulus_pa = 1.1e11});
  const double closed = *law.ClosedFormContactDuration(
      options.ball.MassKg(), options.ball.RadiusM(), result.impacts[0].speed_in_mps);
  EXPECT_NEAR(result.impacts[0].contact_duration_s, closed, 1e-3 * closed);
}

// Quadratic drag, falling from rest: v(h) = v_t sqrt(1 - exp(-2 g h / v_t^2)) with
// v_t = sqrt(g / (drag per mass)). A ping-pong ball (40 mm, 2.7 g) from 2 m. Tolerance 1e-7
// relative: RK4 at <= 1 ms steps on a 0.6 s flight has a truncation error ~1e-10.
TEST(SimulateDrop, AirDragSlowsAFallAsTheClosedFormSays) {
  DropOptions options = PaperDrop();
  options.ball = {.diameter_m = 0.04, .density_kg_per_m3 = 1000, .mass_kg = 0.0027};
  options.drop_height_m = 2;
  options.drag.enabled = true;
  options.max_impacts = 1;
  const DropResult result = SimulateDrop(options);
  ASSERT_EQ(result.impacts.size(), 1u);
  const double c = 0.5 * 1.204 * 0.47 * std::numbers::pi * 0.04 * 0.04 / 4 / 0.0027;
  const double terminal = std::sqrt(9.81 / c);
  const double expected = terminal * std::sqrt(1 - std::exp(-2 * 9.81 * 2 / (terminal * terminal)));
  EXPECT_NEAR(result.impacts[0].speed_in_mps, expected, 1e-7 * expected);
  EXPECT_LT(result.impacts[0].speed_in_mps, std::sqrt(2 * 9.81 * 2) * 0.95);
}

TEST(SimulateDrop, GammaOneSticksAndEndsCleanly) {
  for (Integrator integrator : {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler,
                                Integrator::kRungeKutta4, Integrator::kExact}) {
    DropOptions options = PaperDrop(1.0);
    options.integrator = integrator;
    const DropResult result = SimulateDrop(options);
    EXPECT_EQ(result.stop_reason, DropStopReason::kStuck) << ToString(integrator);
    ASSERT_EQ(result.impacts.size(), 1u);
    EXPECT_EQ(result.impacts[0].restitution, 0);
    EXPECT_FALSE(result.impacts[0].released);
    EXPECT_TRUE(AllFinite(result));
  }
}

// Inelastic collapse: with no rest threshold at all, gravity during contact still ends the
// sequence (slow impacts cannot lift the ball out), after finitely many impacts.
TEST(SimulateDrop, InelasticCollapseEndsInFiniteWorkWithoutRestThreshold) {
  for (Integrator integrator : {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler,
                                Integrator::kRungeKutta4, Integrator::kExact}) {
    DropOptions options = PaperDrop();
    options.integrator = integrator;
    options.rest_flight_s = 0;
    const DropResult result = SimulateDrop(options);
    EXPECT_EQ(result.stop_reason, DropStopReason::kAtRest) << ToString(integrator);
    EXPECT_LT(result.impacts.size(), 100u);
    EXPECT_FALSE(result.impacts.back().released);
  }
}

TEST(SimulateDrop, NonsenseOptionsAreRefusedNamingTheOptionAndRange) {
  const auto message_of = [](const DropOptions& options) {
    try {
      SimulateDrop(options);
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  DropOptions options;
  options.drop_height_m = -1;
  EXPECT_NE(message_of(options).find("drop_height_m"), std::string::npos);
  options = {};
  options.ball.diameter_m = 0;
  EXPECT_NE(message_of(options).find("ball.diameter_m = 0 is outside its valid range [1e-06, 10]"),
            std::string::npos)
      << message_of(options);
  options = {};
  options.gravity_mps2 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message_of(options).find("gravity_mps2"), std::string::npos);
  options = {};
  options.ball.mass_kg = -1;
  EXPECT_NE(message_of(options).find("ball.mass_kg"), std::string::npos);
  options = PaperDrop(2);
  EXPECT_NE(message_of(options).find("gamma_n"), std::string::npos);
  options = {};
  options.time_step_s = 1e-4;
  const std::string unstable = message_of(options);
  EXPECT_NE(unstable.find("stability limit"), std::string::npos) << unstable;
  EXPECT_EQ(unstable.find('\n'), std::string::npos);
  options.allow_unstable_step = true;
  options.max_impacts = 3;
  EXPECT_NO_THROW(SimulateDrop(options));
  options = {};
  options.law.kind = ContactLawKind::kHertz;
  options.integrator = Integrator::kExact;
  EXPECT_NE(message_of(options).find("rk4"), std::string::npos);
  options = {};
  options.integrator = Integrator::kExact;
  options.drag.enabled = true;
  EXPECT_NE(message_of(options).find("drag"), std::string::npos);
  EXPECT_THROW(IntegratorFromString("leapfrog"), ConfigError);
}

TEST(SimulateDrop, StepsPerContactJustAboveTheStabilityLimitIsAccepted) {
  DropOptions options = PaperDrop();
  const DropStep step = ChooseDropStep(options);
  options.steps_per_contact = step.min_steps_per_contact * 1.01;
  EXPECT_NO_THROW(SimulateDrop(options));
  options.steps_per_contact = step.min_steps_per_contact * 0.99;
  EXPECT_THROW(SimulateDrop(options), ConfigError);
}

TEST(SimulateDrop, ResultsAreDeterministic) {
  DropOptions options = PaperDrop();
  options.trajectory_interval_s = 1e-3;
  const DropResult a = SimulateDrop(options);
  const DropResult b = SimulateDrop(options);
  ASSERT_EQ(a.impacts.size(), b.impacts.size());
  for (std::size_t k = 0; k < a.impacts.size(); ++k) {
    EXPECT_EQ(a.impacts[k].time_s, b.impacts[k].time_s);
    EXPECT_EQ(a.impacts[k].restitution, b.impacts[k].restitution);
  }
  EXPECT_EQ(a.trajectory.size(), b.trajectory.size());
  EXPECT_EQ(a.steps, b.steps);
}

// Trajectory points in the first flight lie on the free-fall parabola, at the asked interval.
TEST(SimulateDrop, TrajectoryFollowsTheFreeFall) {
  DropOptions options = PaperDrop();
  options.trajectory_interval_s = 1e-3;
  options.max_impacts = 3;
  const DropResult result = SimulateDrop(options);
  ASSERT_GT(result.trajectory.size(), 200u);
  for (std::size_t i = 0; i < result.trajectory.size(); ++i) {
    const TrajectoryPoint& point = result.trajectory[i];
    EXPECT_NEAR(point.time_s, 1e-3 * static_cast<double>(i), 1e-12);
    if (point.time_s < result.impacts[0].time_s) {
      EXPECT_NEAR(point.height_m, 0.2 - 0.5 * 9.81 * point.time_s * point.time_s, 1e-12);
      EXPECT_NEAR(point.velocity_mps, -9.81 * point.time_s, 1e-12);
    }
  }
}

}  // namespace
}  // namespace bouncecal::dem
