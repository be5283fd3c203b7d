#include "sequences/periodic_sound.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

constexpr double kMainsPeriodS = 1.0 / 60;

std::vector<Impact> Sorted(std::vector<Impact> impacts) {
  std::sort(impacts.begin(), impacts.end(),
            [](const Impact& a, const Impact& b) { return a.onset_s < b.onset_s; });
  return impacts;
}

Impact At(double onset_s, double sigma_s = 20e-6) {
  Impact impact;
  impact.onset_s = onset_s;
  impact.onset_uncertainty_s = sigma_s;
  impact.peak_dbfs = -10;
  return impact;
}

// Mains hum heard as impacts: a lattice of 60 Hz whose slots are heard with probability
// `heard`, each onset off by `jitter_s` (sd; hum_dc as 8 kHz mu-law: 93 of 160 cycles heard,
// pairs within 0.06 ms of a multiple at the median).
void AddHum(std::vector<Impact>& impacts, std::mt19937_64& random, double duration_s,
            double heard = 0.6, double jitter_s = 60e-6) {
  std::bernoulli_distribution is_heard(heard);
  std::normal_distribution<double> jitter(0, jitter_s);
  for (double t = 0.0123; t < duration_s; t += kMainsPeriodS) {
    if (is_heard(random)) impacts.push_back(At(t + jitter(random)));
  }
}

void AddRandomEvents(std::vector<Impact>& impacts, std::mt19937_64& random, double duration_s,
                     double rate_hz) {
  std::exponential_distribution<double> gap_s(rate_hz);
  for (double t = gap_s(random); t < duration_s; t += gap_s(random)) impacts.push_back(At(t));
}

// A drop from t1_s: flights from first_flight_s shrinking by e, each ratio scattered by
// `scatter` (relative sd), until a flight is shorter than the detector's 12 ms min gap.
void AddDrop(std::vector<Impact>& impacts, std::mt19937_64& random, double t1_s,
             double first_flight_s, double e, double scatter = 0.03) {
  std::normal_distribution<double> ratio_noise(0, scatter);
  double t = t1_s, flight = first_flight_s;
  while (flight > 12e-3) {
    impacts.push_back(At(t));
    t += flight;
    flight *= e * (1 + ratio_noise(random));
  }
}

TEST(PeriodicSound, MainsHumHeardAsImpactsGivesItsPeriodAndItsEvents) {
  std::mt19937_64 random(41);
  std::vector<Impact> hum, others;
  AddHum(hum, random, 10);
  AddRandomEvents(others, random, 10, 8);
  std::vector<Impact> impacts = hum;
  impacts.insert(impacts.end(), others.begin(), others.end());
  impacts = Sorted(impacts);

  const auto sound = FindPeriodicSound(impacts, 4e-3, 3);
  ASSERT_TRUE(sound);
  // Hundreds of pairs with 85 us sd each fix the period to well under a microsecond; 2 us
  // allows for the pairs of random events that fall within the lattice's width.
  EXPECT_NEAR(sound->period_s, kMainsPeriodS, 2e-6);
  int hum_on = 0, others_on = 0;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const bool is_hum = std::any_of(
        hum.begin(), hum.end(), [&](const Impact& h) { return h.onset_s == impacts[i].onset_s; });
    (is_hum ? hum_on : others_on) += sound->on_lattice[i] ? 1 : 0;
  }
  // A heard slot has a heard neighbour one or two periods away unless all four are silent
  // (0.4^4 = 2.6 %) or its jitter throws it out of the +-0.3 ms width (pair sd 85 us: 0.05 %).
  EXPECT_GE(hum_on, static_cast<int>(0.95 * static_cast<double>(hum.size())));
  // A random event is on the lattice where one of its four neighbouring slots was heard within
  // the lattice's width (at most 0.5 ms here): 4 x 0.6 x 1 ms / 16.7 ms = 14 %; 80 random events,
  // so at most 30 % (4 sd).
  EXPECT_LE(others_on, static_cast<int>(0.3 * static_cast<double>(others.size())));
  // The width follows the lattice's own scatter: 5 robust sds of its intervals (85 us each), so
  // that the search, which tries every chain along it, does not find the few whose flights the
  // jitter threw out of a narrower one (an hour of this hum formed 2 sequences of 4 consecutive
  // events at 0.3 ms, each with one flight 0.31 ms off). 0.35-0.5 ms: 5 x 85 us, with the sd's
  // estimate from hundreds of pairs good to 10 %.
  EXPECT_GT(sound->half_width_s, 3.5e-4);
  EXPECT_LT(sound->half_width_s, 5e-4);
  std::vector<Impact> chain_impacts;
  std::vector<int> members;
  for (const double t : {2693.25995, 2693.27670, 2693.29349, 2693.30985}) {
    members.push_back(static_cast<int>(chain_impacts.size()));
    chain_impacts.push_back(At(t - 2693.25995 + 1.0123));
  }
  EXPECT_LT(ChanceOfFlightsOnTheLattice(chain_impacts, members, *sound), 1e-3);
}

TEST(PeriodicSound, AClockTickingOnceASecondIsAPeriodToo) {
  std::vector<Impact> impacts;
  for (int k = 0; k < 12; ++k) impacts.push_back(At(0.5 + 1.0004 * k));
  const auto sound = FindPeriodicSound(impacts, 4e-3, 3);
  ASSERT_TRUE(sound);
  EXPECT_NEAR(sound->period_s, 1.0004, 1e-6);
}

// A phone's AGC raised 50 Hz hum to its limiter before a drop, and 11 of 17 cycles were heard as
// impacts (bench/silent_wrong_sweep.py --limiter seed 960 #176, 11 kHz as Opus; these are its
// onsets): no multiple of the period has more than 6 intervals, but 28 of the 33 from one to six
// periods lie on multiples, and the chain of hum events with flights of 8, 4, 2 and 1 periods that
// stood for the drop is chance only along the lattice.
TEST(PeriodicSound, AFewHumCyclesBeforeADropAreAPeriod) {
  std::vector<Impact> impacts;
  for (const double t : {0.01348, 0.21339, 0.23337, 0.27336, 0.29335, 0.33335, 0.37337, 0.43339,
                         0.45337, 0.49337, 0.51336, 0.53337, 0.56601, 0.76987, 0.84537, 1.88671}) {
    impacts.push_back(At(t));
  }
  const auto sound = FindPeriodicSound(impacts, 4e-3, 1.0);
  ASSERT_TRUE(sound);
  EXPECT_NEAR(sound->period_s, 0.02, 0.02e-3);
  EXPECT_EQ(sound->lattice_pairs, 28);
  EXPECT_LT(ChanceOfFlightsOnTheLattice(impacts, {1, 6, 8, 9, 10}, *sound), 1e-3);
  EXPECT_FALSE(sound->on_lattice[12]);  // the drop's first bounce
}

// The period must come from a periodic source, never from the intervals of bouncing balls and
// random sounds: drops of restitution 0.5-0.9 with 3 % scatter (and none, which makes their
// intervals exactly geometric), 1-3 drops per file, among random events at 0-6 per s. The
// search's own chance level is 1e-9 per file, so none of 600 files may show a period.
TEST(PeriodicSound, BouncingBallsAndRandomSoundsShowNoPeriod) {
  int with_period = 0;
  for (int seed = 0; seed < 600; ++seed) {
    std::mt19937_64 random(static_cast<std::uint64_t>(3300 + seed));
    std::uniform_real_distribution<double> uniform(0, 1);
    std::vector<Impact> impacts;
    const int drops = 1 + seed % 3;
    for (int d = 0; d < drops; ++d) {
      AddDrop(impacts, random, 0.5 + 4.0 * d + uniform(random), 0.15 + 0.4 * uniform(random),
              0.5 + 0.4 * uniform(random), seed % 2 == 0 ? 0.03 : 0.0);
    }
    AddRandomEvents(impacts, random, 4.0 * drops + 1, 6 * uniform(random));
    with_period += FindPeriodicSound(Sorted(impacts), 4e-3, 3) ? 1 : 0;
  }
  EXPECT_EQ(with_period, 0);
}

TEST(PeriodicSound, FlightsOnTheLatticeAreChanceOnlyForAChainAlongIt) {
  std::vector<Impact> impacts;
  PeriodicSound sound;
  sound.period_s = kMainsPeriodS;
  sound.half_width_s = 3e-4;
  const auto chance_of = [&](const std::vector<double>& onsets_s) {
    impacts.clear();
    std::vector<int> members;
    for (const double t : onsets_s) {
      members.push_back(static_cast<int>(impacts.size()));
      impacts.push_back(At(t, 60e-6));
    }
    return ChanceOfFlightsOnTheLattice(impacts, members, sound);
  };
  // hum_dc as 8 kHz mu-law: 11 events 5 periods apart (ratios 1.000), and the chain that halves
  // its flights along the lattice once those are refused (ratios 0.50, then 0.785).
  std::vector<double> flat, halving;
  for (int k = 0; k < 11; ++k) flat.push_back(1.8194 + 5 * kMainsPeriodS * k + 1e-4 * (k % 2));
  for (const int slot : {0, 20, 30, 38, 44, 49, 53}) halving.push_back(0.2 + slot * kMainsPeriodS);
  // Each flight lies on a multiple with probability 2 x 0.3 ms / 16.7 ms = 3.6 %: 10 of 10 is
  // 3.6e-15, 6 of 6 2.2e-9.
  EXPECT_LT(chance_of(flat), 1e-12);
  EXPECT_LT(chance_of(halving), 1e-7);
  // A ball's chain whose flights fall at random relative to the period: the chance is a p-value,
  // so below 1e-3 in at most 0.1 % of chains (discreteness makes it fewer): 20 of 10000 is 3 sd
  // above 10.
  std::mt19937_64 random(77);
  std::uniform_real_distribution<double> uniform(0, 1);
  int below = 0;
  for (int chain = 0; chain < 10000; ++chain) {
    std::vector<double> onsets_s = {uniform(random)};
    double flight_s = 0.1 + 0.4 * uniform(random);
    const double e = 0.5 + 0.4 * uniform(random);
    const int count = 4 + chain % 8;
    for (int k = 1; k < count; ++k, flight_s *= e) onsets_s.push_back(onsets_s.back() + flight_s);
    below += chance_of(onsets_s) < 1e-3 ? 1 : 0;
  }
  EXPECT_LE(below, 20);
}

TEST(PeriodicSound, FlightsNearMultiplesOnlyWithinTheirLooseTimingAreNoEvidence) {
  PeriodicSound sound;
  sound.period_s = kMainsPeriodS;
  sound.half_width_s = 3e-4;
  // Flights of 5 periods and 2 ms whose members are timed +-5 ms: beyond the lattice's 0.3 ms,
  // and within 2 x 7 ms of a multiple, which nearly any flight is (q = 0.85 each).
  std::vector<Impact> impacts;
  std::vector<int> members;
  for (int k = 0; k < 6; ++k) {
    members.push_back(k);
    impacts.push_back(At(1 + (5 * kMainsPeriodS + 2e-3) * k, 5e-3));
  }
  EXPECT_GT(ChanceOfFlightsOnTheLattice(impacts, members, sound), 0.5);
  // The same flights on exact multiples lie within the lattice's own width: its count decides.
  for (int k = 0; k < 6; ++k)
    impacts[static_cast<std::size_t>(k)].onset_s = 1 + 5 * kMainsPeriodS * k;
  EXPECT_LT(ChanceOfFlightsOnTheLattice(impacts, members, sound), 1e-6);
}

// A chain's first members that sound like the periodic source (an event one or two periods from
// each, at most 10 dB quieter) before two members off every lattice slot are the source's, not
// the drop's (silent_wrong_sweep.py --limiter seed 970 #124: a hum event 0.49 s before the first
// bounce began the sequence, eta-bar 0.504 against 0.547). Not where the lattice neighbour is a
// faint sound in the member's ringing (a codec's once a frame, 16 dB under), where the members
// after are on slots too (a reflection one period after every bounce), or where too few members
// would be left.
TEST(PeriodicSound, FirstMembersThatSoundLikeTheSourceBeforeTheDropAreItsEvents) {
  constexpr double kPeriodS = 0.02;
  const std::vector<double> bounces = {0.60, 0.97, 1.22, 1.39, 1.505};
  struct Case {
    std::vector<double> leading;  // members before the bounces, each with hum 1-2 periods away
    double neighbour_db;          // the hum's level; the members are at -10 dBFS
    bool reflected;               // a sound one period after every bounce
    std::size_t fewest_left;
    std::size_t expected;
  };
  for (const Case& c : {Case{{0.14}, -10, false, 3, 1}, Case{{0.12, 0.14}, -12, false, 3, 2},
                        Case{{0.14}, -26, false, 3, 0}, Case{{0.14}, -10, true, 3, 0},
                        Case{{0.14}, -10, false, 6, 0}}) {
    SCOPED_TRACE(::testing::Message() << c.leading.size() << " " << c.neighbour_db << " "
                                      << c.reflected << " " << c.fewest_left);
    std::vector<Impact> impacts;
    // Hum from 0 to 0.2 s, every slot heard but the members' own.
    for (int k = 0; k <= 10; ++k) {
      const double t = kPeriodS * k;
      if (std::none_of(c.leading.begin(), c.leading.end(),
                       [&](double member) { return std::fabs(member - t) < 1e-9; })) {
        impacts.push_back(At(t));
        impacts.back().peak_dbfs = c.neighbour_db;
      }
    }
    for (const double t : c.leading) impacts.push_back(At(t));
    for (const double t : bounces) {
      impacts.push_back(At(t));
      if (c.reflected) impacts.push_back(At(t + kPeriodS));
    }
    impacts = Sorted(impacts);
    const auto sound = FindPeriodicSound(impacts, 4e-3, 1.0);
    ASSERT_TRUE(sound);
    std::vector<int> members;
    for (std::size_t i = 0; i < impacts.size(); ++i) {
      const double t = impacts[i].onset_s;
      const bool leading = std::any_of(c.leading.begin(), c.leading.end(),
                                       [&](double member) { return std::fabs(member - t) < 1e-9; });
      const bool bounce = std::any_of(bounces.begin(), bounces.end(),
                                      [&](double b) { return std::fabs(b - t) < 1e-9; });
      if (leading || bounce) members.push_back(static_cast<int>(i));
    }
    EXPECT_EQ(LeadingEventsOfThePeriodicSound(impacts, members, *sound, c.fewest_left), c.expected);
  }
}

}  // namespace
}  // namespace bouncecal::audio
