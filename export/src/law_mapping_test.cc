#include "bouncecal/export/law_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr double kSteelBallMassKg = 7800 * std::numbers::pi * 0.01 * 0.01 * 0.01 / 6;

struct Impact {
  double restitution;
  double contact_duration_s;
};

// The paper's law integrated directly (semi-implicit Euler at 1e6 steps per contact, gravity
// off): loading force (1+g) k xi, unloading (1-g) k xi; contact ends when xi returns to 0.
Impact IntegrateWaltonBraun(double k, double gamma_n, double m_eff, double speed_mps) {
  const double dt = std::sqrt(m_eff / k) * 4e-6;
  double xi = 0, rate = speed_mps, t = 0;
  do {
    const double stiffness = rate > 0 ? (1 + gamma_n) * k : (1 - gamma_n) * k;
    rate -= stiffness * xi / m_eff * dt;
    xi += rate * dt;
    t += dt;
  } while (xi > 0);
  return {-rate / speed_mps, t};
}

TEST(MapWaltonBraun, WallCoefficientsKeepTheLawsRestitutionAndContactDuration) {
  const auto mapping = MapWaltonBraun(1e7, 0.5, kSteelBallMassKg, Engine::kLammps);
  const auto direct = IntegrateWaltonBraun(1e7, 0.5, kSteelBallMassKg, 1.98);
  // The direct integration resolves each contact in ~5e5 steps: its first-order error in e and
  // t_c is ~1e-5 relative, so 1e-4 is a safe bound that still catches any formula slip.
  EXPECT_NEAR(Restitution(mapping.wall) / direct.restitution, 1.0, 1e-4);
  EXPECT_NEAR(ContactDurationS(mapping.wall) / direct.contact_duration_s, 1.0, 1e-4);
  // docs/physics.md: eta = 2 gamma / (1 + gamma) = 2/3 for gamma_n = 0.5; closed forms to rounding.
  EXPECT_NEAR(1 - mapping.restitution * mapping.restitution, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(Restitution(mapping.wall), mapping.restitution, 1e-12);
  EXPECT_FALSE(mapping.exact);
  // The reference contact (m = 4.08 g, k = 1e7 N/m) lasts about 70 us (docs/physics.md section 2).
  EXPECT_NEAR(mapping.wall_contact_duration_s, 70e-6, 2e-6);
}

TEST(MapWaltonBraun, EqualSpherePairsKeepRestitutionAndThePairContactDuration) {
  const auto mapping = MapWaltonBraun(1e7, 0.3, kSteelBallMassKg, Engine::kLammps);
  const auto direct = IntegrateWaltonBraun(1e7, 0.3, 0.5 * kSteelBallMassKg, 0.5);
  EXPECT_DOUBLE_EQ(mapping.pair.effective_mass_kg, 0.5 * kSteelBallMassKg);
  EXPECT_NEAR(Restitution(mapping.pair) / direct.restitution, 1.0, 1e-4);
  EXPECT_NEAR(ContactDurationS(mapping.pair) / direct.contact_duration_s, 1.0, 1e-4);
  // A single gamma_n for walls and pairs would break this; the mapping scales it by sqrt(2).
  EXPECT_NEAR(mapping.pair.damping_rate_per_s / mapping.wall.damping_rate_per_s, std::sqrt(2.0),
              1e-12);
}

TEST(MapWaltonBraun, NotesSayTheLawIsMappedAndGiveTheCoefficients) {
  const auto mapping = MapWaltonBraun(1e7, 0.5, kSteelBallMassKg, Engine::kLammps);
  std::string all;
  for (const auto& note : mapping.notes) all += note + "\n";
  EXPECT_NE(all.find("LAMMPS has no Walton-Braun"), std::string::npos) << all;
  EXPECT_NE(all.find("SAME restitution e = 0.577350"), std::string::npos) << all;
  EXPECT_NE(all.find("m_eff = m/2"), std::string::npos) << all;
  const auto liggghts = MapWaltonBraun(1e7, 0.5, kSteelBallMassKg, Engine::kLiggghts);
  EXPECT_NE(liggghts.notes.front().find("Luding"), std::string::npos) << liggghts.notes.front();
}

TEST(MapWaltonBraun, ElasticLawMapsToAnUndampedSpringWithTheSameStiffness) {
  const auto mapping = MapWaltonBraun(1e7, 0.0, kSteelBallMassKg, Engine::kLammps);
  EXPECT_EQ(mapping.wall.damping_rate_per_s, 0.0);
  EXPECT_NEAR(mapping.wall.stiffness_n_per_m / 1e7, 1.0, 1e-12);
}

TEST(MapWaltonBraun, OutOfRangeParametersAreConfigErrorsNamingTheParameter) {
  try {
    MapWaltonBraun(1e7, 1.0, kSteelBallMassKg, Engine::kLammps);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("gamma_n"), std::string::npos) << error.what();
  }
  EXPECT_THROW(MapWaltonBraun(-1, 0.5, kSteelBallMassKg, Engine::kLammps), ConfigError);
  EXPECT_THROW(MapWaltonBraun(1e7, NAN, kSteelBallMassKg, Engine::kLammps), ConfigError);
  EXPECT_THROW(MapWaltonBraun(1e7, 0.5, 0.0, Engine::kLammps), ConfigError);
}

TEST(MapLinearDashpot, IsExactAndGivesTheCundallStrackRestitution) {
  const double zeta = 0.2;
  const auto mapping = MapLinearDashpot(1e7, zeta, kSteelBallMassKg, Engine::kLammps);
  EXPECT_TRUE(mapping.exact);
  // Damped oscillator: e = exp(-pi zeta / sqrt(1 - zeta^2)) for any m_eff.
  const double expected = std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));
  EXPECT_NEAR(mapping.restitution, expected, 1e-12);
  EXPECT_NEAR(Restitution(mapping.pair), expected, 1e-12);
  EXPECT_THROW(MapLinearDashpot(1e7, 1.0, kSteelBallMassKg, Engine::kLammps), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate

namespace bouncecal::calibrate {
namespace {

dem::ContactLawConfig Law(dem::ContactLawKind kind,
                          std::map<std::string, double, std::less<>> parameters) {
  dem::ContactLawConfig config;
  config.kind = kind;
  config.parameters = std::move(parameters);
  return config;
}

TEST(MapContactLaw, WaltonBraunAgreesWithTheDemClosedForms) {
  const auto config =
      Law(dem::ContactLawKind::kWaltonBraun, {{"stiffness_n_per_m", 2e7}, {"gamma_n", 0.4}});
  const auto mapping = MapContactLaw(config, kSteelBallMassKg, 0.005, 1.98, Engine::kLammps);
  const dem::WaltonBraun law({.stiffness_n_per_m = 2e7, .gamma_n = 0.4});
  // Two implementations of the same closed forms: equal to rounding.
  EXPECT_NEAR(mapping.restitution, *law.ClosedFormRestitution(kSteelBallMassKg, 0.005, 1.98),
              1e-12);
  EXPECT_NEAR(mapping.wall_contact_duration_s /
                  *law.ClosedFormContactDuration(kSteelBallMassKg, 0.005, 1.98),
              1.0, 1e-12);
  EXPECT_NEAR(mapping.pair_contact_duration_s /
                  *law.ClosedFormContactDuration(0.5 * kSteelBallMassKg, 0.0025, 1.98),
              1.0, 1e-12);
}

TEST(MapContactLaw, PlasticWaltonBraunMapsAtEverySpeedAndSaysSo) {
  const auto config = Law(dem::ContactLawKind::kWaltonBraunPlastic,
                          {{"stiffness_n_per_m", 1e7}, {"unloading_stiffness_n_per_m", 4e7}});
  const auto mapping = MapContactLaw(config, kSteelBallMassKg, 0.005, 1.98, Engine::kLiggghts);
  EXPECT_NEAR(Restitution(mapping.wall), 0.5, 1e-12);  // sqrt(k1/k2)
  EXPECT_FALSE(mapping.exact);
  EXPECT_NE(mapping.notes.at(1).find("speed-independent"), std::string::npos)
      << mapping.notes.at(1);
}

TEST(MapContactLaw, HertzMapsAtTheReferenceSpeedAndStatesTheSpeedDependence) {
  const auto config = Law(dem::ContactLawKind::kHertz, {{"effective_modulus_pa", 1.1e11}});
  const auto mapping = MapContactLaw(config, kSteelBallMassKg, 0.005, 1.98, Engine::kLammps);
  EXPECT_EQ(mapping.wall.damping_rate_per_s, 0.0);  // elastic: e = 1
  const dem::Hertz law({.effective_modulus_pa = 1.1e11});
  EXPECT_NEAR(ContactDurationS(mapping.wall) /
                  *law.ClosedFormContactDuration(kSteelBallMassKg, 0.005, 1.98),
              1.0, 1e-12);
  EXPECT_NE(mapping.notes.at(1).find("DEVIATION"), std::string::npos) << mapping.notes.at(1);
}

TEST(MapContactLaw, LawWithoutClosedFormsIsAConfigErrorNamingIt) {
  const auto config = Law(dem::ContactLawKind::kHertzViscoelastic, {});
  try {
    MapContactLaw(config, kSteelBallMassKg, 0.005, 1.98, Engine::kLammps);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("hertz-viscoelastic"), std::string::npos)
        << error.what();
  }
}

// A law that states it has no engine form (thornton: neither engine has its plastic Hertz
// contact, and a one-speed stand-in would drop its speed dependence) is refused in one line with
// its reason, whatever the engine, and the list of laws that can be exported leaves it out.
TEST(MapContactLaw, LawWithoutAnEngineFormIsRefusedWithItsReasonInOneLine) {
  const dem::ContactLawConfig config{.kind = dem::kKindOf<dem::Thornton>, .parameters = {}};
  for (Engine engine : {Engine::kLammps, Engine::kLiggghts}) {
    try {
      MapContactLaw(config, kSteelBallMassKg, 0.005, 1.98, engine);
      FAIL() << "no ConfigError";
    } catch (const ConfigError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("contact law 'thornton' cannot be exported to"), std::string::npos)
          << message;
      EXPECT_NE(message.find("elastic-plastic"), std::string::npos) << message;
      EXPECT_NE(message.find("(fit one of them to the same recordings): walton-braun, "
                             "walton-braun-plastic, linear-dashpot, hertz"),
                std::string::npos)
          << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace bouncecal::calibrate
