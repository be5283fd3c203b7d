#include "sequences/ratio_scatter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <numeric>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// Impacts at the times a ball with these interval ratios makes from a 0.4 s first flight, each
// stated +-sigma_s, and every one of them as the chain's members.
struct Chain {
  std::vector<Impact> impacts;
  std::vector<int> members;
};

Chain FromRatios(const std::vector<double>& ratios, double sigma_s) {
  Chain chain;
  double t = 0.5, flight = 0.4;
  chain.impacts.push_back({.onset_s = t, .onset_uncertainty_s = sigma_s});
  chain.impacts.push_back({.onset_s = t += flight, .onset_uncertainty_s = sigma_s});
  for (double ratio : ratios) {
    flight *= ratio;
    chain.impacts.push_back({.onset_s = t += flight, .onset_uncertainty_s = sigma_s});
  }
  chain.members.resize(chain.impacts.size());
  std::iota(chain.members.begin(), chain.members.end(), 0);
  return chain;
}

constexpr double kScatter = 0.05;

// A constant restitution that scatters by 3 % from impact to impact (the coverage suite's steel
// on copper) over 30 bounces is one ball: against the 5 % the rule allows, its chi-square is
// (3/5)^2 of a 5 % ball's, whose tail passes 1e-3 once in a thousand; five seeds are checked.
TEST(RatioScatter, ABallWhoseRestitutionScattersByAFewPerCentIsOneBall) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> scatter(0.0, 0.03);
    std::vector<double> ratios;
    for (int k = 0; k < 30; ++k) ratios.push_back(0.8 * (1.0 + scatter(random)));
    const Chain chain = FromRatios(ratios, 20e-6);
    EXPECT_GT(ChanceOfRatioScatter(chain.impacts, chain.members, kScatter), 1e-3) << seed;
  }
}

// e rising with falling impact speed (ub-mth337's ping-pong ball: 0.907 -> 0.95 over its
// bounces) is a line in the bounce number, which the test allows whatever its slope.
TEST(RatioScatter, ARestitutionThatDriftsWithImpactSpeedIsOneBall) {
  std::vector<double> ratios;
  for (int k = 0; k < 40; ++k) ratios.push_back(0.907 + 0.043 * k / 39.0);
  const Chain chain = FromRatios(ratios, 20e-6);
  EXPECT_GT(ChanceOfRatioScatter(chain.impacts, chain.members, kScatter), 0.5);
}

// The ratios of the zaky-ptv ping-pong clip's wrong chain at 8 kHz (two bounces and a walk
// through the speech): 15 % from impact to impact, no ball.
TEST(RatioScatter, RatiosThatWalkFarBeyondABallsScatterAreNoBall) {
  const Chain chain =
      FromRatios({0.846, 0.787, 0.723, 0.660, 0.773, 0.678, 0.570, 0.689, 0.856}, 100e-6);
  EXPECT_LT(ChanceOfRatioScatter(chain.impacts, chain.members, kScatter), 1e-6);
}

// The same ratios timed only to +-5 ms (a codec's smeared onsets) are not refused: their
// stated timing covers the walk.
TEST(RatioScatter, ScatterTheStatedTimingCoversIsNoEvidence) {
  const Chain chain =
      FromRatios({0.846, 0.787, 0.723, 0.660, 0.773, 0.678, 0.570, 0.689, 0.856}, 5e-3);
  EXPECT_GT(ChanceOfRatioScatter(chain.impacts, chain.members, kScatter), 1e-2);
}

// Two ratios always lie on a line.
TEST(RatioScatter, FewerThanThreeRatiosAreNeverRefused) {
  const Chain chain = FromRatios({0.3, 0.9}, 1e-6);
  EXPECT_EQ(ChanceOfRatioScatter(chain.impacts, chain.members, kScatter), 1.0);
}

}  // namespace
}  // namespace bouncecal::audio
