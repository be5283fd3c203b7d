// Round trips through every stage: dem::SimulateDrop with known parameters -> the impact times
// and speeds rendered as a recording (plate modes, room reverb, noise) -> WAV -> the audio stage
// (detect, group into a bounce sequence) -> calibrate::Fit must give the parameters back.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/dem/drop.h"
#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal {
namespace {

using bouncecal::testing::ScratchPath;

struct RoundTrip {
  std::filesystem::path wav;
  std::vector<double> true_onsets_s;
};

// Simulates the drop (reference integrator), synthesises its sound and writes a 48 kHz PCM16 WAV.
RoundTrip RecordSimulatedDrop(const dem::ContactLawConfig& law, dem::Integrator integrator,
                              int impacts, double drop_height_m, const std::string& name,
                              std::uint64_t seed) {
  dem::DropOptions drop;
  drop.drop_height_m = drop_height_m;
  drop.law = law;
  drop.integrator = integrator;
  drop.max_impacts = impacts;
  const auto result = dem::SimulateDrop(drop);

  audio::SynthesisOptions synthesis;
  const double release_s = 0.3;
  RoundTrip trip;
  for (const auto& impact : result.impacts) {
    synthesis.impacts.push_back({release_s + impact.time_s, impact.speed_in_mps});
    trip.true_onsets_s.push_back(release_s + impact.time_s);
  }
  synthesis.reverb = audio::ReverbOptions{};  // RT60 0.3 s, DRR 10 dB
  synthesis.noise = audio::NoiseOptions{};    // 35 dB SNR re the first impact
  synthesis.seed = seed;
  const auto recording = audio::SynthesizeBounces(synthesis);
  trip.wav = ScratchPath(name + ".wav");
  audio::WriteRecording(trip.wav, recording.channels);
  return trip;
}

calibrate::MeasuredSequence DetectedSequence(const RoundTrip& trip) {
  const auto sequences = calibrate::LoadSequences({trip.wav});
  EXPECT_EQ(sequences.size(), 1u);
  return sequences.front();
}

TEST(CalibrateRoundTrip, WaltonBraunGammaComesBackFromASynthesizedRecording) {
  const double gamma = 0.408;  // the formula's value for the paper's eta-bar = 0.58
  const auto trip = RecordSimulatedDrop({dem::ContactLawKind::kWaltonBraun, {{"gamma_n", gamma}}},
                                        dem::Integrator::kExact, 12, 0.2, "walton_braun", 3);
  const auto sequence = DetectedSequence(trip);
  // eta-bar of the first 3 impacts needs 4 onsets.
  ASSERT_GE(sequence.impacts.size(), 4u);
  // The detector must have found the first impact: the objective matches impact 1 to the drop.
  EXPECT_NEAR(sequence.impacts.front().onset_s, trip.true_onsets_s.front(), 1e-4);

  calibrate::FitOptions options;  // the paper's method: eta-bar of the first 3, h0 = 0.2 m
  options.drop.drop_height_m = 0.2;
  options.drop_height_given = true;
  const auto summary = calibrate::Fit({sequence}, options);
  const auto& fitted = summary.parameters.front();
  // Tolerance 2e-3 on gamma: the fit's drops use velocity Verlet at the default 50 steps per
  // contact while the recording came from the exact integrator, a bias of ~5e-4 in gamma that
  // the analytic check measures (time_step_gamma_error); onset errors of the detector (<= 10 us
  // median on clean 48 kHz audio, the same sign for similar impacts so they largely cancel in
  // the intervals) move eta-bar by < 1e-4 each, i.e. < 1e-4 in gamma. 2e-3 is twice their sum
  // plus margin for the reverb tail raising the floor under the later impacts.
  EXPECT_NEAR(fitted.value, gamma, 2e-3);
  EXPECT_NEAR(fitted.value + summary.check.time_step_error, gamma, 1e-3)
      << "the measured time-step error should explain most of the bias";
  EXPECT_FALSE(summary.check.warning) << summary.check.message;
}

TEST(CalibrateRoundTrip, HertzViscoelasticDissipativeTimeComesBackFromTheWholeSequence) {
  const double dissipative_time_s = 3e-6;
  const auto trip = RecordSimulatedDrop(
      {dem::ContactLawKind::kHertzViscoelastic, {{"dissipative_time_s", dissipative_time_s}}},
      dem::Integrator::kRungeKutta4, 20, 0.4, "hertz_viscoelastic", 4);
  const auto sequence = DetectedSequence(trip);
  // At least three flights, so the speed dependence is sampled at three impact speeds.
  ASSERT_GE(sequence.impacts.size(), 4u);

  calibrate::FitOptions options;
  options.drop.law = {dem::ContactLawKind::kHertzViscoelastic, {}};
  // The simulated drop's ball: drop.ball's default, calibrate::ReferenceBall().
  options.ball_given = true;
  // From 0.4 m the first impacts come at 2.8 m/s, so the sequence spans a wider speed range.
  options.drop.drop_height_m = 0.4;
  options.drop_height_given = true;
  options.objective = calibrate::FitObjective::kIntervals;
  const auto summary = calibrate::Fit({sequence}, options);
  // 3 %: the speed dependence is weak (e ~ v^(1/5)), so A is set mostly by the mean loss; the
  // detector's onset errors (~10 us on intervals of 20-270 ms) move A by < 0.5 %, the Verlet
  // step at 50 steps per contact by < 0.5 % (its eta error is ~3e-4 of ~0.6); 3 % is a
  // threefold margin for the reverb and noise on the weaker late impacts.
  EXPECT_NEAR(summary.parameters.front().value, dissipative_time_s, 0.03 * dissipative_time_s);
}

// The standard protocol: drops from several heights fitted jointly, each with its own height.
// Both recordings come from one walton-braun material (gamma_n = 0.408, eta = 2 gamma / (1 +
// gamma) = 0.58 at every speed), one dropped from 0.20 m, one from 0.40 m.
TEST(CalibrateRoundTrip, DropsFromTwoHeightsFitJointlyEachWithItsOwnHeight) {
  const double gamma = 0.408;
  const dem::ContactLawConfig law{dem::ContactLawKind::kWaltonBraun, {{"gamma_n", gamma}}};
  const auto low = RecordSimulatedDrop(law, dem::Integrator::kExact, 10, 0.20, "height_low", 5);
  const auto high = RecordSimulatedDrop(law, dem::Integrator::kExact, 10, 0.40, "height_high", 6);
  auto low_sequence = DetectedSequence(low);
  auto high_sequence = DetectedSequence(high);
  low_sequence.drop_height_m = 0.20;
  high_sequence.drop_height_m = 0.40;

  calibrate::FitOptions options;  // no height for all: each sequence carries its own
  const auto summary = calibrate::Fit({low_sequence, high_sequence}, options);
  // 3e-3, the bound: the fit's Verlet drops against the exact recording bias gamma by
  // ~5e-4 (see the single-height test above) and the detector's onset errors add < 1e-4.
  EXPECT_NEAR(summary.parameters.front().value, gamma, 3e-3);
  ASSERT_EQ(summary.sequences.size(), 2u);
  EXPECT_EQ(summary.sequences[0].drop_height_m, 0.20);
  EXPECT_EQ(summary.sequences[1].drop_height_m, 0.40);

  // One height for both is wrong for the 0.40 m drop: its e_1 would be sqrt(2) too large, far
  // beyond any material's scatter, and the fit refuses it, naming the height the bounces imply.
  calibrate::FitOptions one_height;
  one_height.drop.drop_height_m = 0.20;
  one_height.drop_height_given = true;
  low_sequence.drop_height_m.reset();
  high_sequence.drop_height_m.reset();
  try {
    calibrate::Fit({low_sequence, high_sequence}, one_height);
    ADD_FAILURE() << "a 0.40 m drop fitted with 0.20 m was not refused";
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("first impact was probably missed or the height is wrong"),
              std::string::npos)
        << message;
    // The bounces imply the true release height, 0.40 m, to within the detector's timing and the
    // contact time the flights include (0.399 m measured): printed to three digits.
    const auto implied = message.find("imply a release from 0.");
    ASSERT_NE(implied, std::string::npos) << message;
    EXPECT_NEAR(std::stod(message.substr(implied + 21)), 0.40, 0.003) << message;
  }
}

}  // namespace
}  // namespace bouncecal
