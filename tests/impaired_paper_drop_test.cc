// The paper's own experiment (1 cm steel ball, 0.20 m, e = 0.648, a free steel plate that rings
// for seconds) under impairments a real recording brings: per-impact level scatter (where on
// the plate the ball lands) and a room. From the 4th impact on the bounces sit in the plate's
// tail, rise less than the band threshold and are found by the ringing residual alone: weak
// evidence, timed to within a frame hop. They may complete a bounce sequence only where their
// timing could hardly be chance (SequenceOptions::max_chance_alignment), and they must state an
// uncertainty that covers their timing error, so the eta-bar they feed is honest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/calibrate/restitution.h"

namespace bouncecal {
namespace {

struct Outcome {
  bool sequence = false;  // a sequence of at least 5 impacts: eta-bar over the first 3 e values
  bool members_true = true;
  double eta_error = 0;
  double eta_sigma = 0;
};

// eta-bar over the first three e values of exactly timed onsets.
double EtaBarFirstThree(const std::vector<double>& onsets_s) {
  std::vector<calibrate::TimedImpact> impacts;
  for (double t : onsets_s) impacts.push_back({t, 0.0});
  return *calibrate::AnalyzeRestitution(impacts).energy_loss_mean_first_n;
}

Outcome Run(audio::SynthesisOptions options) {
  const auto synthesized = audio::SynthesizeBounces(options);
  const auto truth = synthesized.BallImpactOnsetsS();
  auto detection = audio::DetectImpacts(synthesized.channels[0]);
  const auto grouping = audio::GroupBounces(detection);
  Outcome outcome;
  if (grouping.sequences.empty() || grouping.sequences[0].impact_indices.size() < 5) {
    return outcome;
  }
  outcome.sequence = true;
  std::vector<calibrate::TimedImpact> measured;
  std::vector<double> matched_truth;  // the true onset of each member
  for (int i : grouping.sequences[0].impact_indices) {
    const auto& impact = detection.impacts[static_cast<std::size_t>(i)];
    measured.push_back({impact.onset_s, impact.onset_uncertainty_s});
    double nearest = truth.front();
    for (double t : truth) {
      if (std::fabs(impact.onset_s - t) < std::fabs(impact.onset_s - nearest)) nearest = t;
    }
    // 10 ms: a third of the shortest flight in the sequence; a stray sound would be farther.
    if (std::fabs(impact.onset_s - nearest) > 10e-3) outcome.members_true = false;
    matched_truth.push_back(nearest);
  }
  // Two members on one true impact: not a sequence of this drop's bounces.
  for (std::size_t k = 1; k < matched_truth.size(); ++k) {
    if (!(matched_truth[k] > matched_truth[k - 1])) outcome.members_true = false;
  }
  if (!outcome.members_true) return outcome;
  const auto analysis = calibrate::AnalyzeRestitution(measured);
  // The same impacts' true onsets give the true e values of the same bounces.
  outcome.eta_error = *analysis.energy_loss_mean_first_n - EtaBarFirstThree(matched_truth);
  outcome.eta_sigma = *analysis.energy_loss_mean_first_n_uncertainty;
  return outcome;
}

// Counts and checks the outcomes of 8 seeds of one impairment.
int Check(const std::string& condition, const audio::SynthesisOptions& base) {
  int sequences = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    auto options = base;
    options.seed = seed;
    const Outcome outcome = Run(options);
    if (!outcome.sequence) continue;
    ++sequences;
    std::printf("[ figures  ] %s seed %d: eta-bar error %+.4f, stated sigma %.4f\n",
                condition.c_str(), static_cast<int>(seed), outcome.eta_error, outcome.eta_sigma);
    EXPECT_TRUE(outcome.members_true) << condition << " seed " << seed;
    // The stated uncertainty must cover the error. Before residual-only onsets stated a frame
    // hop, these read +-0.0003 against errors up to 0.013 (40 sigma). 3 sigma: a Gaussian
    // error would exceed it once in 370; the errors measured are within 1.5 sigma.
    EXPECT_LE(std::fabs(outcome.eta_error), 3 * outcome.eta_sigma)
        << condition << " seed " << seed << ": " << outcome.eta_error << " +- "
        << outcome.eta_sigma;
  }
  std::printf("[ figures  ] %s: %d of 8 seeds give a sequence with eta-bar\n", condition.c_str(),
              sequences);
  return sequences;
}

audio::SynthesisOptions PapersDrop(double snr_db) {
  audio::SynthesisOptions options;  // defaults: 0.2 m, e = sqrt(1 - 0.58), free steel plate
  audio::NoiseOptions noise;
  noise.snr_db = snr_db;  // referred to the first impact
  options.noise = noise;
  return options;
}

// Measured 2026-11-24: 3 of 8 seeds with 4 dB of level scatter and 4 of 8 in a 0.5 s room give
// a sequence, where before weak impacts could count none did (0 of 8 each): the other seeds
// find only 3-4 impacts, or their weak ones land too far from the predicted times to exclude
// chance. The bound asks for 2, a margin of one seed against a change in the synthesiser's
// random draws.
TEST(ImpairedPapersDrop, LevelScatterStillGivesASequenceWithAnHonestEtaBar) {
  auto options = PapersDrop(25.0);
  options.level_jitter_db = 4.0;
  EXPECT_GE(Check("level scatter 4 dB, 25 dB SNR", options), 2);
}

TEST(ImpairedPapersDrop, ARoomStillGivesASequenceWithAnHonestEtaBar) {
  auto options = PapersDrop(30.0);
  audio::ReverbOptions room;
  room.rt60_s = 0.5;
  room.direct_to_reverberant_db = 3.0;
  options.reverb = room;
  EXPECT_GE(Check("room RT60 0.5 s, DRR 3 dB", options), 2);
}

}  // namespace
}  // namespace bouncecal
