#include "detector/onset_picker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// A first lobe that starts exactly at onset (fractional sample index) as a (i - onset)^p up to
// its extremum rise_samples later, then swings to the opposite sign along a cosine, the way a
// struck plate's first half-cycle looks.
std::vector<float> Edge(double onset, double power, double rise_samples, double amplitude,
                        double noise_rms, unsigned seed, std::size_t length = 64) {
  std::vector<float> x(length, 0.0f);
  std::mt19937 generator(seed);
  std::normal_distribution<double> noise(0.0, noise_rms);
  for (std::size_t i = 0; i < length; ++i) {
    const double u = static_cast<double>(i) - onset;
    double value = 0;
    if (u > 0 && u <= rise_samples) {
      value = amplitude * std::pow(u / rise_samples, power);
    } else if (u > rise_samples) {
      value = amplitude * std::cos(std::numbers::pi * (u - rise_samples) / (2 * rise_samples));
    }
    x[i] = static_cast<float>(value + (noise_rms > 0 ? noise(generator) : 0.0));
  }
  return x;
}

// A 70 us contact at 48 kHz: its edge is 3 samples long and only two of them are below the
// fit's 60 % ceiling, too few to tell the power from the onset, so the prior (p = 3) decides.
// On a t^3 edge 60 dB above the noise the origin comes out at every sub-sample position to
// 0.1 sample (2 us at 48 kHz; measured at most 0.08, the fit's grid step is 1/64). Edges of
// power 2.5 and 3.5, the plausible physical range, cost the prior's assumption at most 0.35
// sample (7 us at 48 kHz, still under the 10 us target): measured at most 0.28.
TEST(OnsetPicker, ShortEdgeFitFindsTheOriginAtAnySubSamplePosition) {
  for (double power : {2.5, 3.0, 3.5}) {
    for (double fraction : {0.0, 0.25, 0.5, 0.8}) {
      const double onset = 30.0 + fraction;
      const auto x = Edge(onset, power, 3.0, 1.0, 1e-3, 7);
      const auto change_point = static_cast<std::size_t>(std::ceil(onset));
      const auto fit = FitLeadingEdge(x, change_point, 1e-3);
      ASSERT_TRUE(fit.has_value()) << power << " " << fraction;
      EXPECT_NEAR(fit->index, onset, power == 3.0 ? 0.1 : 0.35)
          << "p " << power << " onset " << onset;
      EXPECT_GT(fit->sigma_samples, 0.0);
    }
  }
}

// On a long edge (a 150 us contact at 96 kHz: 12 samples) the data identify the power, from an
// impulsive p = 1 to p = 4, and the origin is found to 0.15 sample for p <= 3 (measured 0.005
// for p = 1 and 1.5, 0.08 for p = 3). The fit allows the power law a 5 % model error, within
// which a p = 4 edge is hard to tell from a slightly later p = 3 one and the prior pulls it
// there: 0.35 sample (measured 0.29).
TEST(OnsetPicker, LongEdgeIdentifiesItsPowerAndOrigin) {
  for (double power : {1.0, 1.5, 3.0, 4.0}) {
    const double onset = 20.37;
    const auto x = Edge(onset, power, 12.0, 0.5, 1e-4, 3);
    const auto fit = FitLeadingEdge(x, 21, 1e-4);
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR(fit->index, onset, power <= 3.0 ? 0.15 : 0.35) << power;
  }
}

// The whole picker (change point, then edge fit) on noisy t^3 edges: over 200 noise
// realisations at 40 dB (lobe peak to noise rms), the median error stays under 0.25 sample
// (5 us at 48 kHz; measured 0.175) and the stated one-sigma uncertainty is honest: |error| <=
// 2 sigma in at least 90 % of the trials (95 % for exact Gaussian errors; measured 97 %).
TEST(OnsetPicker, NoisyEdgesAreTimedWithAnHonestUncertainty) {
  std::vector<double> errors;
  int covered = 0;
  constexpr int kTrials = 200;
  for (int trial = 0; trial < kTrials; ++trial) {
    const double onset = 40.0 + (trial % 10) / 10.0;
    const auto x = Edge(onset, 3.0, 3.0, 1.0, 1e-2, static_cast<unsigned>(trial + 1), 80);
    const auto pick = PickOnset(x, 10, 46);
    const double error = pick.index - onset;
    errors.push_back(std::fabs(error));
    if (std::fabs(error) <= 2 * pick.sigma_samples) ++covered;
  }
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.25);
  EXPECT_GE(covered, kTrials * 90 / 100);
}

// Digital silence before the impact (no noise at all) must not break the fit: the origin of an
// exact t^3 edge comes out to the fit's grid step.
TEST(OnsetPicker, DigitalSilenceBeforeTheEdgeIsHandled) {
  const double onset = 25.6;
  const auto x = Edge(onset, 3.0, 4.0, 0.8, 0.0, 1);
  const auto pick = PickOnset(x, 5, 32);
  EXPECT_TRUE(std::isfinite(pick.index));
  EXPECT_NEAR(pick.index, onset, 0.1);
  EXPECT_GT(pick.sigma_samples, 0.0);
}

// The hidden span is where the edge a u^p is still below 4 noise sigmas: it solves
// a tau^p = 4 sigma_n exactly (to rounding: 1e-12), grows as (sigma_n / a)^(1/p), and is 0
// without noise or without an edge.
TEST(OnsetPicker, HiddenEdgeSpanIsWhereTheEdgeIsBelowFourNoiseSigmas) {
  for (double power : {1.0, 3.0, 3.5}) {
    const double amplitude = 2e-3;
    const double noise_rms = 1e-2;
    const double tau = HiddenEdgeSamples(amplitude, power, noise_rms);
    EXPECT_NEAR(amplitude * std::pow(tau, power), 4 * noise_rms, 1e-12) << power;
    EXPECT_NEAR(HiddenEdgeSamples(amplitude, power, 8 * noise_rms) / tau,
                std::pow(8.0, 1.0 / power), 1e-12)
        << power;
  }
  EXPECT_EQ(HiddenEdgeSamples(1.0, 3.0, 0.0), 0.0);
  EXPECT_EQ(HiddenEdgeSamples(0.0, 3.0, 1e-3), 0.0);
}

// In noise the edge's first samples hide, and the stated sigma must say so (HiddenEdgeSamples):
// the same t^3 edges as above with the lobe only 20 dB over the noise, 200 realisations. At least
// 90 % within 2 sigma (95 % for exact Gaussian errors; the binomial spread over 200 trials is
// 1.5 %): measured 96.5 %, and 80.5 % without the hidden-edge term, which this bound rejects.
TEST(OnsetPicker, EdgesDeepInNoiseStateAnHonestUncertainty) {
  int covered = 0;
  constexpr int kTrials = 200;
  for (int trial = 0; trial < kTrials; ++trial) {
    const double onset = 40.0 + (trial % 10) / 10.0;
    const auto x = Edge(onset, 3.0, 3.0, 1.0, 1e-1, static_cast<unsigned>(trial + 1), 80);
    const auto pick = PickOnset(x, 10, 46);
    if (std::fabs(pick.index - onset) <= 2 * pick.sigma_samples) ++covered;
  }
  std::printf("[ figures  ] within 2 sigma %d/%d\n", covered, kTrials);
  EXPECT_GE(covered, kTrials * 90 / 100);
}

// Noise alone has no lobe standing 4 sigma out near the change point often enough to matter;
// when it has none, the fit declines and the picker keeps the change point.
TEST(OnsetPicker, NoLobeAboveTheNoiseGivesNoEdgeFit) {
  std::vector<float> x(64, 0.0f);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = (i % 2 == 0 ? 1.0f : -1.0f) * 1e-3f;
  EXPECT_FALSE(FitLeadingEdge(x, 32, 1e-3).has_value());
}

// A soft impact: a weak, short first lobe (its contact click) and, a lobe's width later, the
// plate's response, which keeps growing long after it. Taking the reference at a fraction of the
// window's largest sample put it on the click when the click was above that fraction of the body
// and on the body's edge, 8 samples later, when it was below: from impact to impact the ratio
// changes and the intervals jumped by 150-190 us at 48 kHz. The reference belongs on the click
// whatever the ratio (here 6 % to 20 %, across the old 12 %): within 0.5 sample of the same
// point on the click's edge, half its one-sample rise for the noise and the interpolation.
TEST(OnsetPicker, SoftImpactIsTimedOnItsFirstLobeWhateverTheLaterLobesReach) {
  constexpr double kOnset = 40.3;
  constexpr double kClick = 0.05;
  std::vector<double> references;
  for (double click_to_body : {0.06, 0.09, 0.11, 0.13, 0.16, 0.20}) {
    std::vector<float> x(200, 0.0f);
    std::mt19937 generator(11);
    std::normal_distribution<double> noise(0.0, 2e-4);
    const double body = kClick / click_to_body;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double u = static_cast<double>(i) - kOnset;
      double value = 0;
      // The click: up in one sample, down over five.
      if (u > 0) value += kClick * std::min(u, 1.0) * std::exp(-std::max(0.0, u - 1.0) / 3.0);
      // The body: starts 6 samples in, a slow oscillation growing over 100 samples.
      if (u > 6) value += body * std::min(1.0, (u - 6) / 100.0) * std::sin((u - 6) / 8.0);
      x[i] = static_cast<float>(value + noise(generator));
    }
    const OnsetPick pick = PickOnset(x, 30, x.size() - 1);
    ASSERT_TRUE(std::isfinite(pick.reference_index)) << click_to_body;
    EXPECT_GT(pick.reference_index, kOnset - 1.0) << click_to_body;
    EXPECT_LT(pick.reference_index, kOnset + 1.0) << click_to_body;
    references.push_back(pick.reference_index);
  }
  const auto [low, high] = std::minmax_element(references.begin(), references.end());
  EXPECT_LT(*high - *low, 0.5);
}

// What must not be taken for a first lobe. (1) A precursor: a weak click (8 % of the impact's
// peak, above the reference fraction of the precursor's own size but below the impact's) 3 ms
// before the impact, as a ball's release or a rattle makes: a separate sound, which the impact's
// level does not follow within the horizon. (2) A zero-phase filter's pre-ringing in digital
// silence: an oscillation near the band edge growing as 1/distance towards the impact for 80
// samples, each lobe standing out of float rounding but not of the lobe before it. Either way the
// reference belongs on the impact's own edge, within one sample of where its first lobe crosses
// 12 % of its peak (the crossing interpolates between two samples).
// The soft_contact recording of the detector suite in the 2 kHz band: a tail's excursion (a
// plateau at about half the noise floor) ends in the impact's click, whose 12 % level lies in the
// noise and whose edge is one sample long, so neither a reference nor an edge fit is placed and
// the onset is the AIC change point, which falls at the plateau's start. Between that and where
// the impact clears the noise the onset cannot be told: the stated sigma covers both (it was 2.5
// samples, 0.4 of the 9-sample distance; now at least half of it).
TEST(OnsetPicker, AChangePointOnATailsExcursionStatesTheDistanceToTheImpact) {
  constexpr double kNoise = 0.001;
  constexpr std::size_t kPlateau = 100;
  constexpr std::size_t kClick = 110;
  std::vector<float> x(200);
  std::mt19937 generator(7);
  std::normal_distribution<double> noise(0.0, kNoise);
  for (std::size_t i = 0; i < x.size(); ++i) {
    double value = noise(generator);
    if (i >= kPlateau && i < kClick) value += 0.002;
    if (i == kClick) value += 0.011;
    if (i > kClick) {
      value += 0.024 * std::exp(-static_cast<double>(i - kClick) / 60.0) *
               std::sin(2 * std::numbers::pi * static_cast<double>(i - kClick) / 14.0 + 0.3);
    }
    x[i] = static_cast<float>(value);
  }
  const OnsetPick pick = PickOnset(x, 60, 140);
  ASSERT_TRUE(std::isnan(pick.reference_index)) << "not the branch under test";
  ASSERT_LT(pick.index, static_cast<double>(kClick) - 4) << "not the branch under test";
  EXPECT_GE(pick.sigma_samples, 0.5 * (static_cast<double>(kClick) - pick.index) - 1.0);
  // And not without bound: the distance to the click, not the window.
  EXPECT_LE(pick.sigma_samples, static_cast<double>(kClick) - pick.index + 2.0);
}

TEST(OnsetPicker, PrecursorsAndPreRingingAreNotTakenForTheFirstLobe) {
  constexpr double kOnset = 200.4;
  const auto impact = [&](double u) {
    return u > 0 ? std::sin(std::numbers::pi * std::min(u, 3.0) / 6.0) *
                       std::exp(-std::max(0.0, u - 3.0) / 40.0) *
                       std::cos(std::numbers::pi * std::max(0.0, u - 3.0) / 8.0)
                 : 0.0;
  };
  // The impact alone: where its edge crosses 12 % of its peak (1.0).
  const double crossing = kOnset + 6.0 / std::numbers::pi * std::asin(kReferenceFraction);

  std::vector<float> with_precursor(300, 0.0f);
  std::vector<float> with_pre_ringing(300, 0.0f);
  std::mt19937 generator(5);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (std::size_t i = 0; i < with_precursor.size(); ++i) {
    const double u = static_cast<double>(i) - kOnset;
    const double precursor_u = u + 144.0;  // 3 ms before at 48 kHz
    const double precursor =
        precursor_u > 0 ? 0.08 * std::exp(-precursor_u / 4.0) * std::min(precursor_u, 1.0) : 0.0;
    with_precursor[i] = static_cast<float>(impact(u) + precursor + noise(generator));
    const double ringing = u < 0 && u > -80
                               ? 0.02 / (1.0 - u / 2.0) * std::cos(2.2 * std::numbers::pi * u / 5.0)
                               : 0.0;
    with_pre_ringing[i] = static_cast<float>(impact(u) + ringing);
  }
  // ReferenceCrossing is given the noise before the precursor (PickOnset's change point may fall
  // on the impact, and its noise estimate then holds the precursor, which hides it).
  const auto precursor_pick = ReferenceCrossing(with_precursor, 20, 215, 1e-3);
  ASSERT_TRUE(precursor_pick.has_value());
  EXPECT_NEAR(precursor_pick->reference_index, crossing, 1.0);
  const auto ringing_pick = ReferenceCrossing(with_pre_ringing, 20, 215, 0.0);
  ASSERT_TRUE(ringing_pick.has_value());
  EXPECT_NEAR(ringing_pick->reference_index, crossing, 1.0);
}

// A prediction innovation (the ringing of earlier impacts removed, PredictionInnovation) of a
// soft impact: unit noise, then from `onset` a burst burst_db louder for as long as the contact
// pushes (`contact` samples), with a sample of largest_sds burst sds `largest_after` samples in.
std::vector<float> InnovationBurst(std::size_t onset, std::size_t contact,
                                   std::size_t largest_after, double largest_sds, double burst_db,
                                   unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<float> x(onset + 2 * contact);
  const double gain = std::pow(10.0, burst_db / 20.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const bool pushing = i >= onset && i < onset + contact;
    x[i] = static_cast<float>(normal(generator) * (pushing ? gain : 1.0));
  }
  x[onset + largest_after] = static_cast<float>(largest_sds * gain);
  return x;
}

// A 1.3 ms contact at 48 kHz (62 samples) whose innovation stands 4 dB over the noise, its largest
// sample 50 samples in at 8 times the burst's sd (the detector suite's rubber_ball, 11th impact:
// 3 dB at its start, the largest sample 1.3 ms in). Cut at that sample as an edge would be, the
// AIC's second segment is the one or two samples before the cut, and in 32 noise draws the change
// point lands on them in 14, the median error 47.5 samples (1 ms); with 48 more samples (1 ms at
// 48 kHz, OnsetLocator's burst) the median is 13.4 samples, the AIC's own spread for a 4 dB step.
TEST(OnsetPicker, AnInnovationBurstIsPickedWhereItBeginsNotAtItsLargestSample) {
  constexpr std::size_t kOnset = 400;
  constexpr std::size_t kLargest = kOnset + 50;
  constexpr double kBurstDb = 4.0;
  std::vector<double> cut_errors;
  std::vector<double> errors;
  for (unsigned seed = 1; seed <= 32; ++seed) {
    const auto x = InnovationBurst(kOnset, 62, 50, 8.0, kBurstDb, seed);
    const OnsetPick cut =
        PickOnset(std::span<const float>(x).first(kLargest + 2), 100, kLargest + 1);
    cut_errors.push_back(std::fabs(cut.index - static_cast<double>(kOnset)));
    const OnsetPick pick = PickOnsetInInnovation(x, 100, kLargest, 48, 4.0);
    errors.push_back(std::fabs(pick.index - static_cast<double>(kOnset)));
  }
  std::sort(cut_errors.begin(), cut_errors.end());
  std::sort(errors.begin(), errors.end());
  // Half the draws or more on the largest sample without the rest of the burst ...
  EXPECT_GT(cut_errors[16], 40.0);
  // ... and with it the median within 20 samples (measured 13.4).
  EXPECT_LT(errors[16], 20.0);
}

// Where the change point is not on the largest sample, the pick is PickOnset's on the cut window;
// and where the burst does not stand out of the search's start (min_start_aic_excess too high),
// the cut window's pick stays.
TEST(OnsetPicker, AnInnovationPickAwayFromItsLargestSampleIsLeftAsItWas) {
  constexpr std::size_t kOnset = 400;
  const auto x = InnovationBurst(kOnset, 62, 5, 5.0, 12.0, 3);
  const OnsetPick cut = PickOnset(std::span<const float>(x).first(kOnset + 7), 100, kOnset + 6);
  ASSERT_LT(cut.index, static_cast<double>(kOnset + 5) - kDegenerateChangePointSamples);
  EXPECT_EQ(PickOnsetInInnovation(x, 100, kOnset + 5, 48, 4.0).index, cut.index);

  const auto late = InnovationBurst(kOnset, 62, 50, 5.0, 6.0, 1);
  const OnsetPick late_cut =
      PickOnset(std::span<const float>(late).first(kOnset + 52), 100, kOnset + 51);
  EXPECT_EQ(PickOnsetInInnovation(late, 100, kOnset + 50, 48, 1e9).index, late_cut.index);
}

}  // namespace
}  // namespace bouncecal::audio
