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

// With the turning point located, the peak overlap is the integrator's state at v = 0; at 1000
// steps it matches the exact path to the O(dt) of Euler, 1e-3 relative.
TEST(SimulateDrop, PeakOverlapMatchesTheExactPath) {
  DropOptions options = PaperDrop();
  options.max_impacts = 1;
  options.integrator = Integrator::kExact;
  const double exact = SimulateDrop(options).impacts.at(0).max_overlap_m;
  for (Integrator integrator : kSteppedIntegrators) {
    options.integrator = integrator;
    options.steps_per_contact = 1000;
    EXPECT_NEAR(SimulateDrop(options).impacts.at(0).max_overlap_m, exact, 1e-3 * exact)
        << ToString(integrator);
  }
}

TEST(SimulateDrop, EveryStopReasonIsReachedAndExplained) {
  DropOptions options = PaperDrop();
  options.max_impacts = 4;
  DropResult result = SimulateDrop(options);
  EXPECT_EQ(result.stop_reason, DropStopReason::kMaxImpacts);
  EXPECT_EQ(result.impacts.size(), 4u);
  options = PaperDrop();
  options.max_time_s = 0.5;
  result = SimulateDrop(options);
  EXPECT_EQ(result.stop_reason, DropStopReason::kTimeLimit);
  EXPECT_EQ(result.impacts.size(), 2u);  // onsets at 0.202 s and 0.435 s
  options = PaperDrop();
  options.max_steps = 10;
  result = SimulateDrop(options);
  EXPECT_EQ(result.stop_reason, DropStopReason::kStepLimit);
  EXPECT_LE(result.steps, 12);  // a located event may add one sub-step to the last step
  options = PaperDrop();
  options.rest_flight_s = 0.05;  // flights of 0.4 e^k s: rest after impact 4 (0.044 s)
  result = SimulateDrop(options);
  EXPECT_EQ(result.stop_reason, DropStopReason::kAtRest);
  EXPECT_EQ(result.impacts.size(), 4u);
  for (DropStopReason reason :
       {DropStopReason::kMaxImpacts, DropStopReason::kTimeLimit, DropStopReason::kAtRest,
        DropStopReason::kStuck, DropStopReason::kStepLimit}) {
    EXPECT_NE(ToString(reason), "unknown");
  }
}

// The paper's simulated eta-bar = 0.598 (docs/physics.md section 3) is what fixed-step
// stepping at dt = 10 us gives on average over where the touchdown falls inside a step (the
// hysteresis branch switches only at step boundaries); located events give the formula's 0.667.
// Over 100 onset phases the classic mean has a standard error of 0.0046 (spread 0.046), so
// 0.02 is 4 standard errors; the located result is within 0.025 of 0.667 at 7 steps/contact.
TEST(SimulateDrop, ClassicTenMicrosecondStepsReproduceThePaperValue) {
  const auto eta_bar = [](const DropResult& result, double h0) {
    double previous = 2 * std::sqrt(2 * h0 / 9.8), sum = 0;
    for (int k = 0; k < 3; ++k) {
      const double interval = result.impacts.at(k + 1).time_s - result.impacts.at(k).time_s;
      sum += 1 - (interval / previous) * (interval / previous);
      previous = interval;
    }
    return sum / 3;
  };
  DropOptions options = PaperDrop();
  options.gravity_mps2 = 9.8;
  options.time_step_s = 10e-6;
  options.max_impacts = 5;
  options.fixed_step_grid = true;
  options.locate_contact_events = false;
  double mean = 0;
  for (int i = 0; i < 100; ++i) {
    options.drop_height_m = 0.2 + i / 100.0 * std::sqrt(2 * 9.8 * 0.2) * 10e-6;
    mean += eta_bar(SimulateDrop(options), options.drop_height_m) / 100;
  }
  EXPECT_NEAR(mean, 0.598, 0.02);
  options.fixed_step_grid = false;
  options.locate_contact_events = true;
  options.drop_height_m = 0.2;
  EXPECT_NEAR(eta_bar(SimulateDrop(options), 0.2), 2 * 0.5 / 1.5, 0.025);
}

// Every law with a closed-form restitution or contact duration, through the whole drop engine:
// the first impact (RK4, 1000 steps per contact) against the gravity-free closed forms. Gravity
// acting during the contact changes both by a relative amount of order g t_c / v_out; the
// tolerance is 3 g t_c / v_out (the integration error, < 1e-8, is negligible). Brilliantov
// damping is taken small (A = 2e-8 s) so that the two-term series is exact to ~1e-7.
TEST(SimulateDrop, FirstImpactMatchesEveryClosedForm) {
  for (ContactLawKind kind : kAllContactLawKinds) {
    DropOptions options;
    options.law = {.kind = kind, .parameters = {}};
    if (kind == ContactLawKind::kHertzViscoelastic) {
      options.law.parameters["dissipative_time_s"] = 2e-8;
    }
    options.integrator = Integrator::kRungeKutta4;
    options.steps_per_contact = 1000;
    options.max_impacts = 1;
    const DropImpact impact = SimulateDrop(options).impacts.at(0);
    const ContactLaw law = MakeContactLaw(options.law);
    std::visit(
        [&](const auto& typed) {
          const double m = options.ball.MassKg(), r = options.ball.RadiusM();
          const double tolerance =
              3 * options.gravity_mps2 * impact.contact_duration_s / impact.speed_out_mps;
          if (const auto e = typed.ClosedFormRestitution(m, r, impact.speed_in_mps)) {
            EXPECT_NEAR(impact.restitution, *e, tolerance * *e) << ToString(kind);
          }
          if (const auto tc = typed.ClosedFormContactDuration(m, r, impact.speed_in_mps)) {
            EXPECT_NEAR(impact.contact_duration_s, *tc, tolerance * *tc) << ToString(kind);
          }
        },
        law);
  }
}

// Quadratic drag makes a light ball's apparent restitution (from flight intervals, as a
// recording measures it) fall with drop height while the contact's own restitution does not:
// a ping-pong ball (40 mm, 2.7 g) from 0.3 m and 2 m. Tolerance 2e-3 on the law's e: gravity
// during the contact at the two impact speeds.
TEST(SimulateDrop, DragMakesApparentRestitutionDependOnDropHeight) {
  const auto apparent_first = [](double height) {
    DropOptions options;
    options.ball = {.diameter_m = 0.04, .density_kg_per_m3 = 1000, .mass_kg = 0.0027};
    options.drop_height_m = height;
    options.drag.enabled = true;
    options.max_impacts = 2;
    const DropResult result = SimulateDrop(options);
    const double first_flight = result.impacts.at(1).time_s - result.impacts.at(0).time_s;
    return std::pair(first_flight / (2 * std::sqrt(2 * height / 9.81)),
                     result.impacts.at(0).restitution);
  };
  const auto [low_apparent, low_true] = apparent_first(0.3);
  const auto [high_apparent, high_true] = apparent_first(2.0);
  EXPECT_NEAR(low_true, high_true, 2e-3);  // the law's e (speed ratio) barely changes
  // Drag slows both the fall from h0 and the following flight, so the ratio to the drag-free
  // dt_0 = 2 sqrt(2 h0 / g) drops with height: 0.57 from 0.3 m, 0.49 from 2 m.
  EXPECT_LT(high_apparent, low_apparent - 0.05);
}

}  // namespace
}  // namespace bouncecal::dem
