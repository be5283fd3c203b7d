#include "bouncecal/export/spring_dashpot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kSteelBallMassKg = 7800 * std::numbers::pi * 0.01 * 0.01 * 0.01 / 6;

struct Bounce {
  double restitution;
  double contact_duration_s;
};

// Integrates one sphere-on-wall impact of the law with classical RK4 at a step far below the
// contact time, independently of the closed forms (gravity off, as they assume).
Bounce IntegrateImpact(const SpringDashpot& law, double impact_speed_mps) {
  const double dt = ContactDurationS(law) * 1e-5;
  auto acceleration = [&](double xi, double rate) {
    return -(law.stiffness_n_per_m * xi / law.effective_mass_kg + law.damping_rate_per_s * rate);
  };
  double xi = 0, rate = impact_speed_mps, t = 0;
  while (true) {
    const double k1x = rate, k1v = acceleration(xi, rate);
    const double k2x = rate + 0.5 * dt * k1v, k2v = acceleration(xi + 0.5 * dt * k1x, k2x);
    const double k3x = rate + 0.5 * dt * k2v, k3v = acceleration(xi + 0.5 * dt * k2x, k3x);
    const double k4x = rate + dt * k3v, k4v = acceleration(xi + dt * k3x, k4x);
    const double next_xi = xi + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double next_rate = rate + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (next_xi <= 0) {
      // Linear interpolation of the separation instant within the last step.
      const double fraction = xi / (xi - next_xi);
      return {-(rate + fraction * (next_rate - rate)) / impact_speed_mps, t + fraction * dt};
    }
    xi = next_xi;
    rate = next_rate;
    t += dt;
  }
}

TEST(SpringDashpot, MatchedLawHasTheRequestedRestitutionAndDuration) {
  for (double e : {0.1, 0.5773502691896257, 0.9, 1.0}) {
    const auto law = MatchRestitutionAndDuration(e, 7.08e-5, kSteelBallMassKg);
    // Closed form inverted in closed form: only rounding separates them.
    EXPECT_NEAR(Restitution(law), e, 1e-12) << e;
    EXPECT_NEAR(ContactDurationS(law), 7.08e-5, 1e-17) << e;
  }
}

TEST(SpringDashpot, ClosedFormsAgreeWithADirectIntegrationOfTheImpact) {
  const auto law = MatchRestitutionAndDuration(0.5773502691896257, 7.08e-5, kSteelBallMassKg);
  const auto bounce = IntegrateImpact(law, 1.98);
  // RK4 at 1e5 steps per contact has a local error far below 1e-12; the separation instant is
  // interpolated linearly within one step (error ~ step^2 curvature), so 1e-7 relative holds for
  // both, and the answer does not depend on the impact speed (a linear law).
  EXPECT_NEAR(bounce.restitution, 0.5773502691896257, 1e-7);
  EXPECT_NEAR(bounce.contact_duration_s / 7.08e-5, 1.0, 1e-7);
  EXPECT_NEAR(IntegrateImpact(law, 0.01).restitution, bounce.restitution, 1e-9);
}

TEST(SpringDashpot, DampingAgreesWithTheLiggghtsRestitutionFormula) {
  // docs/physics.md section 4 (LIGGGHTS model hooke with coefficientRestitution): the damping
  // coefficient is 2 sqrt(m_eff k) (-ln e) / sqrt(pi^2 + ln^2 e), an independent closed form.
  const double e = 0.5773502691896257;
  const auto law = MatchRestitutionAndDuration(e, 7.08e-5, kSteelBallMassKg);
  const double log_e = std::log(e);
  const double expected = 2 * std::sqrt(kSteelBallMassKg * law.stiffness_n_per_m) * (-log_e) /
                          std::sqrt(std::numbers::pi * std::numbers::pi + log_e * log_e);
  EXPECT_NEAR(law.damping_rate_per_s * law.effective_mass_kg / expected, 1.0, 1e-12);
}

TEST(SpringDashpot, HalvingTheMassKeepsStiffnessButNeedsRootTwoMoreDampingRate) {
  // A pair of equal spheres (m_eff = m/2) must keep e while t_c shrinks by sqrt(2), as the
  // Walton-Braun law does: then k is unchanged and gamma_n grows by sqrt(2).
  const double e = 0.6, t_c = 7e-5;
  const auto wall = MatchRestitutionAndDuration(e, t_c, kSteelBallMassKg);
  const auto pair = MatchRestitutionAndDuration(e, t_c / std::sqrt(2.0), kSteelBallMassKg / 2);
  EXPECT_NEAR(pair.stiffness_n_per_m / wall.stiffness_n_per_m, 1.0, 1e-12);
  EXPECT_NEAR(pair.damping_rate_per_s / wall.damping_rate_per_s, std::sqrt(2.0), 1e-12);
}

TEST(SpringDashpot, OverdampedContactNeverRebounds) {
  SpringDashpot law{1e7, 1e6, kSteelBallMassKg};  // beta^2 = 2.5e11 > k/m = 2.4e9
  EXPECT_EQ(Restitution(law), 0.0);
  EXPECT_TRUE(std::isinf(ContactDurationS(law)));
}

TEST(SpringDashpot, ImpossibleTargetsAreConfigErrors) {
  EXPECT_THROW(MatchRestitutionAndDuration(0.0, 7e-5, 0.004), ConfigError);
  EXPECT_THROW(MatchRestitutionAndDuration(1.2, 7e-5, 0.004), ConfigError);
  EXPECT_THROW(MatchRestitutionAndDuration(NAN, 7e-5, 0.004), ConfigError);
  EXPECT_THROW(MatchRestitutionAndDuration(0.5, 0.0, 0.004), ConfigError);
  EXPECT_THROW(MatchRestitutionAndDuration(0.5, INFINITY, 0.004), ConfigError);
  EXPECT_THROW(MatchRestitutionAndDuration(0.5, 7e-5, -1.0), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
