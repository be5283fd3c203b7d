#include "bouncecal/calibrate/contact_stiffness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kPi = std::numbers::pi;

dem::Ball Tennis() { return FindBallPreset("tennis").ToBall(); }

// The first impact's contact as the drop engine measures it, for a ball arriving at `speed`.
// Gravity 1e-3 m/s^2 (released from v^2 / 2g) leaves the gravity-free closed form within
// g / (omega v) ~ 1e-6 of the contact duration, so the comparison isolates the stiffness.
double SimulatedContactS(const dem::ContactLawConfig& law, const dem::Ball& ball, double speed,
                         dem::Integrator integrator) {
  dem::DropOptions drop;
  drop.law = law;
  drop.ball = ball;
  drop.gravity_mps2 = 1e-3;
  drop.drop_height_m = speed * speed / (2 * drop.gravity_mps2);
  drop.max_time_s = 2 * speed / drop.gravity_mps2;
  drop.max_impacts = 1;
  drop.integrator = integrator;
  drop.steps_per_contact = 2000;
  const auto result = dem::SimulateDrop(drop);
  EXPECT_FALSE(result.impacts.empty());
  return result.impacts.empty() ? 0 : result.impacts.front().contact_duration_s;
}

TEST(ContactStiffness, LinearLawsInvertTheirClosedForms) {
  const auto ball = Tennis();
  const double m = ball.MassKg(), t = 5e-3, v = std::sqrt(2 * 9.81 * 1.0);
  // walton-braun: k_n = m (pi/2)^2 (1/sqrt(1 + gamma) + 1/sqrt(1 - gamma))^2 / t_c^2.
  const auto walton =
      WithContactDuration({dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.3}}}, ball, v, t);
  const double branches = 1 / std::sqrt(1.3) + 1 / std::sqrt(0.7);
  EXPECT_NEAR(walton.Get("stiffness_n_per_m"), m * kPi * kPi / 4 * branches * branches / (t * t),
              1e-9 * walton.Get("stiffness_n_per_m"));
  EXPECT_DOUBLE_EQ(walton.Get("gamma_n"), 0.3);  // the damping stays as it was
  // linear-dashpot: k = m pi^2 / ((1 - zeta^2) t_c^2).
  const auto dashpot = WithContactDuration(
      {dem::ContactLawKind::kLinearDashpot, {{"damping_ratio", 0.2}}}, ball, v, t);
  EXPECT_NEAR(dashpot.Get("stiffness_n_per_m"), m * kPi * kPi / ((1 - 0.04) * t * t),
              1e-9 * dashpot.Get("stiffness_n_per_m"));
  // 2.4e4 N/m for a tennis ball at gamma_n 0.3: 400 times below the 1e7 default.
  EXPECT_GT(walton.Get("stiffness_n_per_m"), 1e4);
  EXPECT_LT(walton.Get("stiffness_n_per_m"), 3e4);
}

TEST(ContactStiffness, HertzModulusFollowsTheImpactSpeed) {
  // t_c = 2 I xi_max / v, xi_max = (15 m v^2 / (16 E* sqrt R))^(2/5), I = Gamma(1.4) sqrt(pi) /
  // Gamma(0.9) (physics.md): E* = (2 I / t_c)^(5/2) 15 m / (16 sqrt(R v)), a v^(-1/2) dependence.
  const auto ball = FindBallPreset("golf").ToBall();
  const double m = ball.MassKg(), r = ball.RadiusM(), t = 1e-3;
  const double integral = std::tgamma(1.4) * std::sqrt(kPi) / std::tgamma(0.9);
  for (double v : {1.0, 4.0}) {
    const auto hertz = WithContactDuration({dem::ContactLawKind::kHertz, {}}, ball, v, t);
    const double expected = std::pow(2 * integral / t, 2.5) * 15 * m / (16 * std::sqrt(r * v));
    // Both sides evaluate the same closed form: rounding only.
    EXPECT_NEAR(hertz.Get("effective_modulus_pa"), expected, 1e-9 * expected) << v;
    EXPECT_NEAR(*ContactDurationS(hertz, ball, v), t, 1e-12) << v;
  }
}

// The derived stiffness, simulated: the drop's measured contact lasts the duration asked for.
TEST(ContactStiffness, ASimulatedDropWithTheDerivedStiffnessLastsTheGivenDuration) {
  const auto ball = Tennis();
  const double v = 4.43;
  for (double t : {5e-3, 2e-4}) {
    const auto walton =
        WithContactDuration({dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.3}}}, ball, v, t);
    // The exact path's only error is gravity's, ~1e-6 here (see SimulatedContactS).
    EXPECT_NEAR(SimulatedContactS(walton, ball, v, dem::Integrator::kExact), t, 1e-5 * t) << t;
    const auto dashpot = WithContactDuration(
        {dem::ContactLawKind::kLinearDashpot, {{"damping_ratio", 0.2}}}, ball, v, t);
    EXPECT_NEAR(SimulatedContactS(dashpot, ball, v, dem::Integrator::kExact), t, 1e-5 * t) << t;
    // RK4 at 2000 steps per contact: its error is far below the 1e-5 allowed.
    const auto hertz = WithContactDuration({dem::ContactLawKind::kHertz, {}}, ball, v, t);
    EXPECT_NEAR(SimulatedContactS(hertz, ball, v, dem::Integrator::kRungeKutta4), t, 1e-5 * t) << t;
  }
}

TEST(ContactStiffness, RefusesWhatItCannotDeriveInOneLine) {
  const auto ball = Tennis();
  for (double bad : {0.0, -1e-3, std::nan("")}) {
    try {
      WithContactDuration({dem::ContactLawKind::kWaltonBraun, {}}, ball, 4, bad);
      FAIL() << bad;
    } catch (const ConfigError& error) {
      EXPECT_NE(std::string(error.what()).find("positive number of seconds"), std::string::npos);
    }
  }
  // hertz-viscoelastic has no closed-form duration: the message names the option to use.
  try {
    WithContactDuration({dem::ContactLawKind::kHertzViscoelastic, {}}, ball, 4, 5e-3);
    FAIL();
  } catch (const ConfigError& error) {
    // The parameter to give instead, by its name (each front end has its own way to set it).
    EXPECT_NE(std::string(error.what()).find("give the law's "), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).find("--"), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
  }
}

TEST(ContactStiffness, WarnsWhenANamedBallsStiffnessIsLeftAtTheDefault) {
  const auto ball = Tennis();
  const double v = 4.43;
  const dem::ContactLawConfig defaults{dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.2}}};
  // k_n = 1e7 N/m: (pi/2) sqrt(0.0577 / 1e7) (1/sqrt(1.2) + 1/sqrt(0.8)) = 0.2423 ms, 20 times
  // shorter than a tennis ball's 5 ms.
  EXPECT_NEAR(*ContactDurationS(defaults, ball, v), 2.4233e-4, 0.0001e-4);
  const auto warning = ContactDurationWarning(defaults, ball, "tennis", v);
  EXPECT_NE(warning.find("last 242 us at 4.43 m/s"), std::string::npos) << warning;
  EXPECT_NE(warning.find("5 ms"), std::string::npos) << warning;
  EXPECT_NE(warning.find("`contact_duration_s=0.005`"), std::string::npos) << warning;
  EXPECT_EQ(warning.find('\n'), std::string::npos);
  // A stiffness the user gave (or --contact-duration-s set), or a ball without a known duration:
  // no warning.
  auto given = defaults;
  given.parameters["stiffness_n_per_m"] = 1e7;
  EXPECT_EQ(ContactDurationWarning(given, ball, "tennis", v), "");
  EXPECT_EQ(
      ContactDurationWarning(defaults, FindBallPreset("steel-10mm").ToBall(), "steel-10mm", v), "");
  EXPECT_EQ(ContactDurationWarning(defaults, ball, "", v), "");
  EXPECT_EQ(ContactDurationWarning(WithContactDuration(defaults, ball, v, 4e-3), ball, "tennis", v),
            "");
}

}  // namespace
}  // namespace bouncecal::calibrate
