#include "bouncecal/audio/bounce_sequences.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

// Impact times of a ball dropped at t0 - sqrt(2 h / g) from h with restitution e(k).
std::vector<double> Drop(double t1_s, double first_flight_s, double e, int count,
                         double e_step = 0.0) {
  std::vector<double> times = {t1_s};
  double flight = first_flight_s;
  for (int k = 1; k < count; ++k) {
    times.push_back(times.back() + flight);
    flight *= std::min(0.99, e + e_step * k);
  }
  return times;
}

std::vector<Impact> ToImpacts(std::vector<double> times, double level_dbfs = -10) {
  std::sort(times.begin(), times.end());
  std::vector<Impact> impacts;
  for (double t : times) {
    Impact impact;
    impact.onset_s = t;
    impact.onset_uncertainty_s = 20e-6;
    impact.peak_dbfs = level_dbfs;
    impacts.push_back(impact);
  }
  return impacts;
}

TEST(BounceSequences, DefaultOptionsAreValid) { EXPECT_NO_THROW(SequenceOptions{}.Validate()); }

TEST(BounceSequences, AnIdealDropIsOneSequenceEndingInChatter) {
  const auto times = Drop(0.5, 0.4, 0.8, 30);
  const auto result = FindBounceSequences(ToImpacts(times));
  ASSERT_EQ(result.sequences.size(), 1u);
  const auto& members = result.sequences[0].impact_indices;
  // Flights 0.4 * 0.8^k stay >= 20 ms for k <= 13, so 15 impacts, the rest is chatter.
  EXPECT_EQ(members.size(), 15u);
  EXPECT_EQ(members.front(), 0);
  EXPECT_NE(result.sequences[0].end_reason.find("chatter"), std::string::npos)
      << result.sequences[0].end_reason;
  EXPECT_EQ(result.rejected.size(), times.size() - 15);
}

TEST(BounceSequences, KnockBeforeTheDropIsRejectedWithAReason) {
  auto times = Drop(1.0, 0.3, 0.65, 8);
  times.push_back(0.2);  // knuckle on the table
  const auto result = FindBounceSequences(ToImpacts(times));
  ASSERT_EQ(result.sequences.size(), 1u);
  EXPECT_EQ(result.sequences[0].impact_indices.front(), 1);
  ASSERT_FALSE(result.rejected.empty());
  EXPECT_NEAR(result.rejected[0].time_s, 0.2, 1e-12);
  EXPECT_NE(result.rejected[0].reason.find("before sequence 0"), std::string::npos);
}

TEST(BounceSequences, StraySoundBetweenBouncesIsRejected) {
  auto times = Drop(0.5, 0.5, 0.85, 10);
  const double stray = times[2] + 0.3 * (times[3] - times[2]);
  times.push_back(stray);
  auto impacts = ToImpacts(times);
  for (auto& impact : impacts) {
    if (impact.onset_s == stray) impact.peak_dbfs = -24;  // quieter, like basketball's 2.736 s
  }
  const auto result = FindBounceSequences(impacts);
  ASSERT_EQ(result.sequences.size(), 1u);
  EXPECT_EQ(result.sequences[0].impact_indices.size(), 10u);
  ASSERT_EQ(result.rejected.size(), 1u);
  EXPECT_NEAR(result.rejected[0].time_s, stray, 1e-12);
  EXPECT_NE(result.rejected[0].reason.find("between bounces 3 and 4"), std::string::npos)
      << result.rejected[0].reason;
}

TEST(BounceSequences, SpeedDependentRestitutionIsAccepted) {
  // e rising from 0.785 to 0.83, as in the Fr4nci tennis-ball recording.
  const auto times = Drop(0.3, 1.2, 0.785, 10, 0.005);
  const auto result = FindBounceSequences(ToImpacts(times));
  ASSERT_EQ(result.sequences.size(), 1u);
  EXPECT_EQ(result.sequences[0].impact_indices.size(), 10u);
}

TEST(BounceSequences, SeveralDropsGiveSeveralSequences) {
  auto times = Drop(0.5, 0.4, 0.7, 9);
  const auto second = Drop(4.0, 0.45, 0.7, 9);
  times.insert(times.end(), second.begin(), second.end());
  const auto result = FindBounceSequences(ToImpacts(times));
  ASSERT_EQ(result.sequences.size(), 2u);
  EXPECT_EQ(result.sequences[0].impact_indices.front(), 0);
  EXPECT_EQ(result.sequences[1].impact_indices.front(), 9);
}

TEST(BounceSequences, FewImpactsOrRandomSoundsFormNoSequence) {
  EXPECT_TRUE(FindBounceSequences(ToImpacts({1.0})).sequences.empty());
  EXPECT_TRUE(FindBounceSequences(ToImpacts({1.0, 1.3})).sequences.empty());
  EXPECT_TRUE(FindBounceSequences(ToImpacts({1.0, 1.3, 1.5})).sequences.empty());
  // Intervals that grow are not a bouncing ball.
  const auto result = FindBounceSequences(ToImpacts({1.0, 1.1, 1.3, 1.7, 2.5}));
  EXPECT_TRUE(result.sequences.empty());
  EXPECT_EQ(result.rejected.size(), 5u);
}

TEST(BounceSequences, BadOptionsAreConfigErrors) {
  SequenceOptions options;
  options.max_ratio = 0.5;
  EXPECT_THROW(FindBounceSequences({}, options), ConfigError);
}

// Impacts that only the ringing residual found (Impact::residual_only) are weak evidence: they
// continue a sequence where a bounce is due, but never start one, and make up its minimum count
// only where their timing could hardly be chance.
TEST(BounceSequences, ResidualOnlyImpactsContinueASequenceButNeverMakeOne) {
  const auto times = Drop(0.5, 0.4, 0.8, 8);
  auto impacts = ToImpacts(times);
  // The last four are buried in the tail: found by the residual only, at the tail's level.
  for (std::size_t i = 4; i < impacts.size(); ++i) {
    impacts[i].residual_only = true;
    impacts[i].peak_dbfs = -3;
  }
  // A residual-only stray 30 ms after the 5th bounce, nowhere near where the 6th is due.
  Impact stray = impacts[4];
  stray.onset_s += 0.03;
  impacts.insert(impacts.begin() + 5, stray);
  const auto result = FindBounceSequences(impacts);
  ASSERT_EQ(result.sequences.size(), 1u);
  std::vector<double> members;
  for (int i : result.sequences[0].impact_indices) {
    members.push_back(impacts[static_cast<std::size_t>(i)].onset_s);
  }
  EXPECT_EQ(members, times);
  ASSERT_EQ(result.rejected.size(), 1u);
  EXPECT_DOUBLE_EQ(result.rejected[0].time_s, stray.onset_s);

  // A run of residual-only impacts alone never starts one, however well it fits.
  auto weak = ToImpacts(times);
  for (auto& impact : weak) impact.residual_only = true;
  EXPECT_TRUE(FindBounceSequences(weak).sequences.empty());
}

// Three impacts that rose in a band and then only residual-only ones: fewer than min_impacts
// strong ones, so the chain counts only if its timing cannot be chance (max_chance_alignment).
TEST(BounceSequences, WeakImpactsMakeUpASequenceOnlyWhereTheyLandOnTheBounceTimes) {
  const auto times = Drop(0.5, 0.4, 0.8, 8);
  // On the drop's times (20 us onset sigma): the five weak impacts land within microseconds of
  // t_{k-1} + r dt_{k-1}, which random events at 5 per 1.6 s would do with p ~ 1e-3 each.
  auto on_time = ToImpacts(times);
  for (std::size_t i = 3; i < on_time.size(); ++i) on_time[i].residual_only = true;
  const auto result = FindBounceSequences(on_time);
  ASSERT_EQ(result.sequences.size(), 1u);
  EXPECT_EQ(result.sequences[0].impact_indices.size(), times.size());
  // Weak events that still fit the ratio window (+-0.12 per step) but land 15-26 ms from where
  // each bounce was due: as likely as chance for events at their rate, so no sequence.
  std::vector<double> off_times(times.begin(), times.begin() + 3);  // 0.5, 0.9, 1.22
  for (double t : {1.45, 1.63, 1.75, 1.84, 1.905}) off_times.push_back(t);
  auto off = ToImpacts(off_times);
  for (std::size_t i = 3; i < off.size(); ++i) off[i].residual_only = true;
  EXPECT_TRUE(FindBounceSequences(off).sequences.empty());
  // It is the timing that rejects them: accepting any timing makes them a sequence.
  SequenceOptions any_timing;
  any_timing.max_chance_alignment = 1;
  ASSERT_EQ(FindBounceSequences(off, any_timing).sequences.size(), 1u);
  EXPECT_GE(FindBounceSequences(off, any_timing).sequences[0].impact_indices.size(), 5u);
  // A long chain (200 weak members, e = 0.99) keeps the tail of its score finite.
  auto long_drop = ToImpacts(Drop(0.5, 1.0, 0.99, 203));
  for (std::size_t i = 3; i < long_drop.size(); ++i) long_drop[i].residual_only = true;
  const auto long_result = FindBounceSequences(long_drop);
  ASSERT_EQ(long_result.sequences.size(), 1u);
  EXPECT_EQ(long_result.sequences[0].impact_indices.size(), long_drop.size());
  // The same with max_chance_alignment 0 restores the strict count: no weak impact counts.
  SequenceOptions strict;
  strict.max_chance_alignment = 0;
  EXPECT_TRUE(FindBounceSequences(on_time, strict).sequences.empty());
}

// Tentative impacts (rises too weak to count alone) become impacts only where they continue a
// sequence, near t_n + r dt_n.
TEST(BounceSequences, TentativeImpactsExtendASequenceOnlyWhereTheNextBounceIsDue) {
  const auto times = Drop(0.5, 0.4, 0.8, 10);
  const std::vector<double> strong_times(times.begin(), times.begin() + 6);
  // The last four bounces are tentative, and so are three noise events: one 30 ms after the
  // 8th bounce (a ratio of 0.2, far from 0.8), two before the drop.
  std::vector<double> tentative_times(times.begin() + 6, times.end());
  tentative_times.push_back(times[7] + 0.03);
  tentative_times.push_back(0.1);
  tentative_times.push_back(0.3);
  const auto extended =
      ExtendSequencesWithTentative(ToImpacts(strong_times), ToImpacts(tentative_times));
  std::vector<double> onsets;
  for (const auto& impact : extended) onsets.push_back(impact.onset_s);
  EXPECT_EQ(onsets, times);
  for (std::size_t i = 0; i < extended.size(); ++i) EXPECT_EQ(extended[i].residual_only, i >= 6);
  // Without a sequence to continue nothing is adopted.
  EXPECT_EQ(ExtendSequencesWithTentative(ToImpacts({0.5, 0.9}), ToImpacts(tentative_times)).size(),
            2u);
}

// The window for each adoption is placed with the ratio of the detected bounces: an adopted
// impact that sits at the edge of its window (ratio 0.85 where 0.8 is due, inside the +-0.06
// half tolerance) must not move the next window to ratios near 0.85 + 0.06 = 0.91.
TEST(BounceSequences, AnAdoptedImpactDoesNotSteerTheNextWindow) {
  const auto times = Drop(0.5, 0.4, 0.8, 6);
  const double dt = times[5] - times[4];
  const double adopted = times[5] + 0.85 * dt;
  // 0.91 is outside 0.8 +- 0.06 but inside 0.85 +- 0.06.
  const double steered = adopted + 0.91 * (adopted - times[5]);
  const auto extended =
      ExtendSequencesWithTentative(ToImpacts(times), ToImpacts({adopted, steered}));
  ASSERT_EQ(extended.size(), times.size() + 1);
  EXPECT_EQ(extended.back().onset_s, adopted);
}

}  // namespace
}  // namespace bouncecal::audio
