#include "engine/rest_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace bouncecal::dem::scene {
namespace {

// Kinetic-energy histories sampled every 10 ms after a peak of 1 J, with 1000 particles
// throughout unless a test pours more.
std::vector<HistoryPoint> History(double (*energy_j)(double t_s), int samples,
                                  std::int64_t particles = 1000) {
  std::vector<HistoryPoint> history;
  for (int i = 0; i < samples; ++i) {
    HistoryPoint point;
    point.time_s = 0.01 * i;
    point.kinetic_energy_j = energy_j(point.time_s);
    point.particles = particles;
    history.push_back(point);
  }
  return history;
}

TEST(RestChecks, PackSettlingUnderItsDampingIsNeitherBoilingNorFlaggedOnceAtRest) {
  // e-folding time 20 ms: after 0.5 s the energy is e^-25 of its peak, far under 1 %.
  const auto settled = History([](double t) { return std::exp(-t / 0.02); }, 51);
  EXPECT_FALSE(NotAtRest(settled).has_value());
  EXPECT_FALSE(Boiling(settled));
}

TEST(RestChecks, PackCutShortWhileStillCoolingIsNotAtRestButNotBoiling) {
  // e-folding 0.1 s, cut at 0.3 s: 5 % of the peak is left (not at rest), but the second half
  // since the peak lost 1 - e^-1.5 = 78 % of its energy, more than the half a boiling pack keeps.
  const auto cut = History([](double t) { return std::exp(-t / 0.1); }, 31);
  EXPECT_TRUE(NotAtRest(cut).has_value());
  EXPECT_FALSE(Boiling(cut));
}

TEST(RestChecks, PackWhoseEnergyStopsFallingAboveTheRestLevelIsBoiling) {
  // Falls to a plateau of 30 % of its peak: heated by its integrator as fast as it is damped.
  const auto boiling = History([](double t) { return 0.3 + 0.7 * std::exp(-t / 0.02); }, 41);
  EXPECT_TRUE(NotAtRest(boiling).has_value());
  EXPECT_TRUE(Boiling(boiling));
}

TEST(RestChecks, BoilingMessageGivesWhereTheEnergyStoppedFallingAndTheStep) {
  // The plateau above ends at 0.3 + 0.7 e^-20 J against a peak of 1 J: 30 % of it.
  const auto boiling = History([](double t) { return 0.3 + 0.7 * std::exp(-t / 0.02); }, 41);
  const std::string message = BoilingMessage(boiling, 2e-5);
  EXPECT_NE(message.find("never came to rest"), std::string::npos) << message;
  EXPECT_NE(message.find("0.3 J (30 % of its peak)"), std::string::npos) << message;
  EXPECT_NE(message.find("step of 2e-05 s"), std::string::npos) << message;
  EXPECT_NE(message.find("smaller time_step_s"), std::string::npos) << message;
}

TEST(RestChecks, PackStillFallingOrStillBeingPouredIsNotBoiling) {
  // Particles falling gain energy to the end: the peak is the last sample.
  const auto falling = History([](double t) { return 1.0 + t; }, 41);
  EXPECT_FALSE(Boiling(falling));
  // A plateau while particles are still poured in after the peak is the pour's, not the step's.
  auto poured = History([](double t) { return 0.3 + 0.7 * std::exp(-t / 0.02); }, 41);
  poured.back().particles += 100;
  EXPECT_FALSE(Boiling(poured));
}

}  // namespace
}  // namespace bouncecal::dem::scene
