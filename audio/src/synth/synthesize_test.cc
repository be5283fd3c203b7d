#include "bouncecal/audio/synthesize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>
#include <string>

#include "bouncecal/audio/impact_csv.h"
#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

constexpr double kG = 9.81;

// Options with one or more explicit impacts and no impairments: the bare renderer.
SynthesisOptions ExplicitImpacts(std::vector<ImpactSpec> impacts) {
  SynthesisOptions options;
  options.impacts = std::move(impacts);
  options.tail_s = 0.3;
  return options;
}

double MeanSquare(std::span<const float> samples) {
  double sum = 0.0;
  for (float x : samples) sum += static_cast<double>(x) * x;
  return samples.empty() ? 0.0 : sum / static_cast<double>(samples.size());
}

double PeakIn(const Recording& recording, double from_s, double to_s) {
  const auto from = static_cast<size_t>(from_s * recording.sample_rate_hz);
  const auto to =
      std::min(recording.samples.size(), static_cast<size_t>(to_s * recording.sample_rate_hz));
  double peak = 0.0;
  for (size_t i = from; i < to; ++i) peak = std::max(peak, std::abs(double{recording.samples[i]}));
  return peak;
}

TEST(SynthesizeBounces, DefaultOptionsAreValid) {
  const SynthesisOptions options;
  EXPECT_NO_THROW(ValidateSynthesisOptions(options));
  const SynthesizedRecording recording = SynthesizeBounces(options);
  ASSERT_EQ(recording.channels.size(), 1u);
  EXPECT_EQ(recording.channels[0].sample_rate_hz, 48000);
  EXPECT_GT(recording.BallImpactOnsetsS().size(), 5u);
}

TEST(RectangularPlateModes, FrequenciesFollowKirchhoffTheoryAndDecaysTheLossFactor) {
  RectangularPlate plate;
  plate.min_frequency_hz = 0.0;
  const auto modes = RectangularPlateModes(plate);
  ASSERT_FALSE(modes.empty());
  // Fundamental (1, 1) of a simply supported 0.15 x 0.10 x 0.001 m steel plate:
  // D = 200e9 * 1e-9 / (12 (1 - 0.29^2)) = 18.20 N m, sqrt(D / rho h) = 1.5276 m^2/s,
  // f_11 = pi / 2 * 1.5276 * (1 / 0.15^2 + 1 / 0.10^2) = 346.6 Hz.
  const double d = 200e9 * 1e-9 / (12 * (1 - 0.29 * 0.29));
  const double f11 = std::numbers::pi / 2 * std::sqrt(d / 7.8) * (1 / 0.0225 + 1 / 0.01);
  EXPECT_NEAR(modes.front().frequency_hz, f11, 1e-9 * f11);
  for (const PlateMode& mode : modes) {
    EXPECT_NEAR(mode.decay_s, 1 / (std::numbers::pi * 1e-3 * mode.frequency_hz), 1e-12);
    EXPECT_LE(std::abs(mode.gain), 1.0);
  }
  // Asymptotic modal density of a thin plate: area / 2 * sqrt(rho h / D) modes per Hz
  // (Cremer & Heckl, "Structure-Borne Sound"); simply supported edges lose ~ a perimeter term,
  // so allow 15 % below 15 kHz.
  const double density = 0.015 / 2 * std::sqrt(7.8 / d);
  EXPECT_NEAR(static_cast<double>(modes.size()), density * 15000, 0.15 * density * 15000);
}

TEST(TableTopModes, AWoodenTableRingsLowAndBriefly) {
  const auto modes = TableTopModes();
  ASSERT_FALSE(modes.empty());
  // f_11 of the simply supported 0.9 x 0.6 x 0.018 m plate, E = 10 GPa, 650 kg/m^3, nu = 0.3:
  // D = 10e9 * 0.018^3 / (12 (1 - 0.09)) = 5340.7 N m, f_11 = pi / 2 sqrt(D / 11.7) (1 / 0.81 +
  // 1 / 0.36) = 134.7 Hz: a table's lowest mode lies an octave and more under a steel plate's.
  const double d = 10e9 * 0.018 * 0.018 * 0.018 / (12 * (1 - 0.09));
  const double f11 = std::numbers::pi / 2 * std::sqrt(d / (650 * 0.018)) * (1 / 0.81 + 1 / 0.36);
  EXPECT_NEAR(modes.front().frequency_hz, f11, 1e-9 * f11);
  EXPECT_LE(modes.back().frequency_hz, 6000.0);
  // Loss factor 0.02: 1 / (pi 0.02 f), 118 ms at the lowest mode, 2.7 ms at 6 kHz.
  for (const PlateMode& mode : modes) {
    EXPECT_NEAR(mode.decay_s, 1 / (std::numbers::pi * 0.02 * mode.frequency_hz), 1e-12);
  }
}

TEST(SynthesizeBounces, BallisticImpactTimesFollowTheAnalyticSeries) {
  SynthesisOptions options;
  options.drop.drop_height_m = 0.20;
  options.drop.release_s = 0.25;
  options.drop.restitution.constant = 0.7;
  options.drop.min_flight_s = 0.01;
  const std::vector<SynthesizedEvent> impacts = PlanBallImpacts(options);
  ASSERT_GE(impacts.size(), 10u);
  // Constant e: t_1 = release + sqrt(2 h0 / g), v_k = e^(k-1) v_1, t_{k+1} = t_k + 2 e v_k / g,
  // so t_k = t_1 + (2 v_1 / g) sum_{j=1}^{k-1} e^j in closed form. The planner sums flights one
  // by one; 1e-12 s allows for that rounding over tens of impacts, far below one sample.
  const double v1 = std::sqrt(2 * kG * 0.20);
  const double t1 = 0.25 + std::sqrt(2 * 0.20 / kG);
  for (size_t k = 0; k < impacts.size(); ++k) {
    const double e = 0.7;
    const double geometric = e * (1 - std::pow(e, static_cast<double>(k))) / (1 - e);
    EXPECT_NEAR(impacts[k].onset_s, t1 + 2 * v1 / kG * geometric, 1e-12) << "impact " << k;
    EXPECT_NEAR(impacts[k].impact_speed_mps, v1 * std::pow(e, static_cast<double>(k)), 1e-12);
  }
  // The drop stops at the first flight shorter than min_flight_s.
  const double last_flight = 2 * 0.7 * impacts.back().impact_speed_mps / kG;
  EXPECT_LT(last_flight, 0.01);
  EXPECT_GE(impacts[impacts.size() - 1].onset_s - impacts[impacts.size() - 2].onset_s, 0.01);
}

TEST(SynthesizeBounces, SpeedDependentRestitutionIsEvaluatedAtEachImpactSpeed) {
  SynthesisOptions options;
  options.drop.restitution.constant = 0.9;
  options.drop.restitution.slope_per_mps = -0.1;  // e falls with impact speed
  const auto impacts = PlanBallImpacts(options);
  ASSERT_GE(impacts.size(), 4u);
  for (size_t k = 0; k + 2 < impacts.size(); ++k) {
    const double v = impacts[k].impact_speed_mps;
    const double e = 0.9 - 0.1 * v;
    // Rebound speed from the planner and from the next flight agree to rounding.
    EXPECT_NEAR(impacts[k + 1].impact_speed_mps, e * v, 1e-12);
    EXPECT_NEAR(impacts[k + 1].onset_s - impacts[k].onset_s, 2 * e * v / kG, 1e-12);
  }
  // A user callback wins over the linear law.
  options.drop.restitution.callback = [](double) { return 0.5; };
  const auto halves = PlanBallImpacts(options);
  EXPECT_NEAR(halves[1].impact_speed_mps, 0.5 * halves[0].impact_speed_mps, 1e-12);
}

TEST(SynthesizeBounces, AirDragShortensFlightsAndVanishesForAFastTerminalSpeed) {
  SynthesisOptions options;
  options.drop.drop_height_m = 1.0;
  options.drop.restitution.constant = 0.85;
  const auto vacuum = PlanBallImpacts(options);
  options.drop.terminal_speed_mps = 9.0;  // a ping-pong ball
  const auto air = PlanBallImpacts(options);
  // The first fall: t = (v_t / g) acosh(exp(g h / v_t^2)), v = v_t sqrt(1 - exp(-2 g h / v_t^2))
  // (closed form for quadratic drag), slower and later than in vacuum.
  const double x = kG * 1.0 / 81.0;
  EXPECT_NEAR(air[0].onset_s - 0.3, 9.0 / kG * std::acosh(std::exp(x)), 1e-12);
  EXPECT_NEAR(air[0].impact_speed_mps, 9.0 * std::sqrt(1 - std::exp(-2 * x)), 1e-12);
  EXPECT_GT(air[0].onset_s, vacuum[0].onset_s);
  // Every flight is shorter than the ballistic 2 u / g of its launch speed, and the ball lands
  // slower than it left (drag takes energy on the way up and down).
  for (size_t k = 0; k + 1 < air.size(); ++k) {
    const double launch = 0.85 * air[k].impact_speed_mps;
    EXPECT_LT(air[k + 1].onset_s - air[k].onset_s, 2 * launch / kG);
    EXPECT_LT(air[k + 1].impact_speed_mps, launch);
  }
  // For a fast terminal speed the drag correction is second order, ~1 / v_t^2: ten times v_t
  // must shrink every time shift a hundredfold (1 % allows the next order, (v / v_t)^4). This
  // also fails if the closed form loses precision as v_t grows.
  options.drop.terminal_speed_mps = 1e4;
  const auto fast = PlanBallImpacts(options);
  options.drop.terminal_speed_mps = 1e5;
  const auto faster = PlanBallImpacts(options);
  ASSERT_EQ(fast.size(), vacuum.size());
  ASSERT_EQ(faster.size(), vacuum.size());
  for (size_t k = 0; k < fast.size(); ++k) {
    const double ratio =
        (vacuum[k].onset_s - fast[k].onset_s) / (vacuum[k].onset_s - faster[k].onset_s);
    EXPECT_NEAR(ratio, 100.0, 1.0) << "impact " << k;
  }
}

TEST(SynthesizeBounces, SeveralDropsAreSeparatedBySilence) {
  SynthesisOptions options;
  options.drop.drop_count = 3;
  options.drop.gap_between_drops_s = 0.8;
  const SynthesizedRecording recording = SynthesizeBounces(options);
  for (int d = 0; d < 3; ++d) EXPECT_GT(recording.BallImpactOnsetsS(d).size(), 3u);
  const double last_of_first = recording.BallImpactOnsetsS(0).back();
  const double first_of_second = recording.BallImpactOnsetsS(1).front();
  EXPECT_NEAR(first_of_second - last_of_first, 0.8 + std::sqrt(2 * 0.20 / kG), 1e-12);
}

TEST(SynthesizeBounces, SignalIsExactlyZeroBeforeTheFirstOnsetAndNotAfter) {
  // Echoes and a diffuse reverb tail are on: neither may leak before the direct sound (the
  // reverb is an FFT convolution, whose rounding would otherwise smear before the onset).
  SynthesisOptions options = ExplicitImpacts({{0.1234567, 2.0}, {0.3, 1.5}});
  options.reverb = ReverbOptions{.rt60_s = 0.2, .echoes = {Echo{}}};
  const SynthesizedRecording recording = SynthesizeBounces(options);
  const std::vector<float>& x = recording.channels[0].samples;
  const double onset_samples = 0.1234567 * 48000;
  const auto first_after = static_cast<size_t>(std::ceil(onset_samples));
  for (size_t i = 0; i < first_after; ++i) ASSERT_EQ(x[i], 0.0f) << "sample " << i;
  // The first sample after the onset lies 0.58 samples (12 us) into a 70 us contact: small but
  // non-zero; by 1 ms the plate rings at a good fraction of the requested peak amplitude.
  EXPECT_NE(x[first_after], 0.0f);
  EXPECT_GT(PeakIn(recording.channels[0], 0.1234567, 0.1244567), 0.05);
}

TEST(SynthesizeBounces, EchoesAndPrecursorsAreExactScaledCopiesOfTheImpact) {
  SynthesisOptions dry = ExplicitImpacts({{0.1000123, 1.5}});
  SynthesisOptions wet = dry;
  // 9 ms and 7 ms are 432 and 336 samples at 48 kHz, so the copies line up sample for sample.
  wet.reverb = ReverbOptions{.rt60_s = 0.0, .echoes = {{0.009, -12.0}}};
  wet.precursor = PrecursorOptions{.lead_s = 0.007, .gain_db = -20.0};
  const auto a = SynthesizeBounces(dry).channels[0].samples;
  const auto b = SynthesizeBounces(wet).channels[0].samples;
  const double echo = std::pow(10.0, -12.0 / 20.0);
  const double precursor = std::pow(10.0, -20.0 / 20.0);
  const auto at = [&](std::ptrdiff_t i) {
    return i >= 0 && i < std::ssize(a) ? double{a[static_cast<size_t>(i)]} : 0.0;
  };
  double worst = 0.0;
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i + 336 < a.size(); ++i) {  // a ends 336 samples early for the precursor
    const auto n = static_cast<std::ptrdiff_t>(i);
    // main + echo of main + precursor + the precursor's own echo
    const double expected =
        at(n) + echo * at(n - 432) + precursor * at(n + 336) + precursor * echo * at(n + 336 - 432);
    worst = std::max(worst, std::abs(b[i] - expected));
  }
  EXPECT_LT(worst, 1e-6);  // float rounding of four overlapping copies
}

class EverySampleRate : public ::testing::TestWithParam<int> {};

TEST_P(EverySampleRate, RendersTheDropWithExactSilenceBeforeTheFirstOnset) {
  SynthesisOptions options;
  options.sample_rate_hz = GetParam();
  const auto recording = SynthesizeBounces(options);
  const Recording& channel = recording.channels[0];
  EXPECT_EQ(channel.sample_rate_hz, GetParam());
  const double first_onset_s = recording.BallImpactOnsetsS().front();
  const auto first_after = static_cast<size_t>(std::ceil(first_onset_s * GetParam()));
  for (size_t i = 0; i < first_after; ++i) ASSERT_EQ(channel.samples[i], 0.0f) << i;
  // Only modes under 0.45 x rate are kept, and peak_amplitude (0.5) is normalised over those,
  // so every rate peaks near 0.5; the first onset is off-sample, so the sampled peak can miss
  // the crest of the highest kept modes (up to ~25 % at 8 kHz).
  EXPECT_GT(PeakIn(channel, first_onset_s, first_onset_s + 0.01), 0.35);
  EXPECT_LT(PeakIn(channel, 0.0, channel.duration_s()), 1.0);
}

INSTANTIATE_TEST_SUITE_P(SynthesizeBounces, EverySampleRate,
                         ::testing::Values(8000, 16000, 24000, 44100, 48000, 96000));

TEST(SynthesizeBounces, FractionalOnsetShiftMovesTheWaveformBySubSampleTime) {
  // Rendering at rate f with the onset a quarter sample later must equal rendering at 4 f with
  // the original onset and taking every fourth sample one fine step early: both evaluate the
  // same analytic waveform at the same times. Modes stay below 0.45 f so both rates keep all.
  SynthesisOptions base = ExplicitImpacts({{0.05, 2.0}});
  base.sample_rate_hz = 24000;
  base.modes = {{1500.0, 0.05, 1.0}, {4200.0, 0.02, 0.6}, {9100.0, 0.01, 0.4}};
  base.duration_s = 0.1;
  const double quarter_s = 0.25 / 24000;
  SynthesisOptions shifted = base;
  shifted.impacts[0].onset_s += quarter_s;
  SynthesisOptions fine = base;
  fine.sample_rate_hz = 96000;
  const auto coarse = SynthesizeBounces(shifted).channels[0].samples;
  const auto unshifted = SynthesizeBounces(base).channels[0].samples;
  const auto reference = SynthesizeBounces(fine).channels[0].samples;
  double max_error = 0.0;
  double max_shift_effect = 0.0;
  for (size_t i = 1; i < coarse.size(); ++i) {
    max_error = std::max(max_error, std::abs(double{coarse[i]} - reference[4 * i - 1]));
    max_shift_effect = std::max(max_shift_effect, std::abs(double{coarse[i]} - unshifted[i]));
  }
  // Float storage rounds at ~6e-8 relative to values of ~0.5; 1e-6 leaves margin. A quarter-
  // sample shift itself changes samples by far more (a 9 kHz mode moves by ~0.4 rad).
  EXPECT_LT(max_error, 1e-6);
  EXPECT_GT(max_shift_effect, 0.05);
}

TEST(SynthesizeBounces, AmplitudeGrowsLinearlyWithImpactSpeedForARigidContact) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 0.5}, {1.1, 1.0}, {2.1, 2.0}});
  options.contact_duration_speed_exponent = 0.0;  // same pulse shape: response scales exactly
  options.modes = {{2000.0, 0.05, 1.0}};
  const auto recording = SynthesizeBounces(options);
  const double p1 = PeakIn(recording.channels[0], 0.1, 0.2);
  const double p2 = PeakIn(recording.channels[0], 1.1, 1.2);
  const double p3 = PeakIn(recording.channels[0], 2.1, 2.2);
  // Each impact has decayed by 1e-8 before the next; float rounding ~1e-7 relative.
  EXPECT_NEAR(p2 / p1, 2.0, 1e-5);
  EXPECT_NEAR(p3 / p2, 2.0, 1e-5);

  // With the default Hertz contact (shorter, brighter pulses when faster) it still grows.
  options.contact_duration_speed_exponent = -0.2;
  options.modes = SteelPlateModes();
  const auto hertz = SynthesizeBounces(options);
  EXPECT_LT(PeakIn(hertz.channels[0], 0.1, 0.2), PeakIn(hertz.channels[0], 1.1, 1.2));
  EXPECT_LT(PeakIn(hertz.channels[0], 1.1, 1.2), PeakIn(hertz.channels[0], 2.1, 2.2));
}

TEST(SynthesizeBounces, ReferenceSpeedImpactPeaksAtTheRequestedAmplitude) {
  // Onset on a sample: the sampled peak is exactly the one peak_amplitude is normalised by.
  SynthesisOptions options = ExplicitImpacts({{0.1, 1.98}});
  options.peak_amplitude = 0.3;
  const auto recording = SynthesizeBounces(options);
  EXPECT_NEAR(PeakIn(recording.channels[0], 0.1, 0.15), 0.3, 1e-6);  // float rounding
  EXPECT_DOUBLE_EQ(recording.events[0].peak_amplitude, 0.3);         // and the truth says so
  // Twice the speed, twice the peak for a rigid (speed-independent) contact duration.
  options.impacts[0].impact_speed_mps = 2 * 1.98;
  options.contact_duration_speed_exponent = 0.0;
  EXPECT_NEAR(PeakIn(SynthesizeBounces(options).channels[0], 0.1, 0.15), 0.6, 2e-6);
}

// Measures the SNR exactly as NoiseOptions defines it, from a render with and without noise.
double MeasuredSnrDb(const SynthesisOptions& noisy, double reference_onset_s) {
  SynthesisOptions clean_options = noisy;
  clean_options.noise.reset();
  const auto clean = SynthesizeBounces(clean_options).channels[0].samples;
  const auto with_noise = SynthesizeBounces(noisy).channels[0].samples;
  std::vector<float> noise(clean.size());
  for (size_t i = 0; i < clean.size(); ++i) noise[i] = with_noise[i] - clean[i];
  const double rate = noisy.sample_rate_hz;
  const auto from = static_cast<size_t>(std::ceil(reference_onset_s * rate));
  const auto to = from + static_cast<size_t>(std::llround(noisy.noise->window_s * rate));
  const double signal = MeanSquare(std::span(clean).subspan(from, to - from));
  return 10 * std::log10(signal / MeanSquare(noise));
}

TEST(SynthesizeBounces, MeasuredSnrMatchesTheRequestForWhiteAndPinkNoise) {
  for (NoiseColor color : {NoiseColor::kWhite, NoiseColor::kPink}) {
    // One impact: the window power is the impact's own direct sound.
    SynthesisOptions options = ExplicitImpacts({{0.2, 1.0}});
    options.noise = NoiseOptions{.snr_db = 10.0, .color = color};
    // The noise is rescaled to its exact power; the residue is float rounding of signal + noise
    // (~1e-7 relative), so 0.01 dB is generous yet would catch any definitional slip.
    EXPECT_NEAR(MeasuredSnrDb(options, 0.2), 10.0, 0.01);
  }
}

TEST(SynthesizeBounces, WeakestImpactReferenceSetsTheNoiseByTheQuietestImpact) {
  SynthesisOptions options = ExplicitImpacts({{0.2, 2.0}, {0.7, 0.5}});
  options.noise = NoiseOptions{.snr_db = 20.0, .reference = SnrReference::kWeakestImpact};
  options.modes = {{2000.0, 0.02, 1.0}};
  EXPECT_NEAR(MeasuredSnrDb(options, 0.7), 20.0, 0.01);  // tolerance as above
  options.noise->reference = SnrReference::kFirstImpact;
  EXPECT_NEAR(MeasuredSnrDb(options, 0.2), 20.0, 0.01);
}

TEST(SynthesizeBounces, SameSeedGivesIdenticalSamplesAndAnotherSeedOtherNoise) {
  SynthesisOptions options;
  options.noise = NoiseOptions{.snr_db = 30.0};
  options.reverb = ReverbOptions{};
  options.level_jitter_db = 1.0;
  options.seed = 7;
  const auto a = SynthesizeBounces(options);
  const auto b = SynthesizeBounces(options);
  EXPECT_EQ(a.channels[0].samples, b.channels[0].samples);
  options.seed = 8;
  const auto c = SynthesizeBounces(options);
  ASSERT_EQ(a.channels[0].samples.size(), c.channels[0].samples.size());
  EXPECT_NE(a.channels[0].samples, c.channels[0].samples);
  // The impact times are physics, not chance: the seed must not move them.
  EXPECT_EQ(a.BallImpactOnsetsS(), c.BallImpactOnsetsS());
}

TEST(SynthesizeBounces, SecondChannelIsADelayedScaledCopyWithItsOwnNoise) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 2.0}});
  options.channels = {ChannelOptions{}, ChannelOptions{.delay_s = 0.00025, .gain_db = -6.0}};
  const auto recording = SynthesizeBounces(options);
  ASSERT_EQ(recording.channels.size(), 2u);
  EXPECT_EQ(recording.channel_delay_s, (std::vector<double>{0.0, 0.00025}));
  const auto& left = recording.channels[0].samples;
  const auto& right = recording.channels[1].samples;
  // 0.25 ms is exactly 12 samples at 48 kHz; -6 dB is a factor 0.50119. Float rounding 1e-6.
  const double gain = std::pow(10.0, -6.0 / 20.0);
  for (size_t i = 0; i + 12 < left.size(); ++i) {
    ASSERT_NEAR(right[i + 12], gain * left[i], 1e-6) << "sample " << i;
  }
  options.noise = NoiseOptions{.snr_db = 20.0};
  const auto noisy = SynthesizeBounces(options);
  EXPECT_NE(noisy.channels[0].samples[10], 0.0f);
  // Independent noise: the two channels' noise before the onset is uncorrelated.
  double cross = 0, l2 = 0, r2 = 0;
  for (size_t i = 0; i < 4000; ++i) {
    cross += double{noisy.channels[0].samples[i]} * noisy.channels[1].samples[i];
    l2 += double{noisy.channels[0].samples[i]} * noisy.channels[0].samples[i];
    r2 += double{noisy.channels[1].samples[i]} * noisy.channels[1].samples[i];
  }
  // For 4000 independent samples the correlation coefficient has sigma 1/sqrt(4000) = 0.016.
  EXPECT_LT(std::abs(cross / std::sqrt(l2 * r2)), 0.08);
}

TEST(SynthesizeBounces, TruthListsPrecursorsAndNonBallEventsWithTheirKinds) {
  SynthesisOptions options;
  options.precursor = PrecursorOptions{.lead_s = 0.007};
  options.extra_events = {{SoundEventKind::kKnock, 0.05, 0.3},
                          {SoundEventKind::kThump, 0.15, 0.2},
                          {SoundEventKind::kStray, 0.9, 0.1}};
  const auto recording = SynthesizeBounces(options);
  const auto onsets = recording.BallImpactOnsetsS();
  int knocks = 0, thumps = 0, strays = 0, precursors = 0;
  for (const auto& event : recording.events) {
    switch (event.kind) {
      case SoundEventKind::kKnock:
        ++knocks;
        EXPECT_DOUBLE_EQ(event.onset_s, 0.05);
        EXPECT_EQ(event.drop_index, -1);
        break;
      case SoundEventKind::kThump:
        ++thumps;
        break;
      case SoundEventKind::kStray:
        ++strays;
        break;
      case SoundEventKind::kPrecursor:
        ++precursors;
        EXPECT_TRUE(std::any_of(onsets.begin(), onsets.end(), [&](double t) {
          return std::abs(t - 0.007 - event.onset_s) < 1e-12;
        }));
        break;
      case SoundEventKind::kBallImpact:
        break;
    }
  }
  EXPECT_EQ(knocks, 1);
  EXPECT_EQ(thumps, 1);
  EXPECT_EQ(strays, 1);
  EXPECT_EQ(precursors, static_cast<int>(onsets.size()));
  EXPECT_TRUE(std::is_sorted(recording.events.begin(), recording.events.end(),
                             [](const auto& a, const auto& b) { return a.onset_s < b.onset_s; }));
  // The knock really sounds, near its requested peak (sampled peak of the analytic shape).
  EXPECT_NEAR(PeakIn(recording.channels[0], 0.05, 0.1), 0.3, 0.03);
  const std::string csv = TruthCsv(recording);
  EXPECT_EQ(csv.rfind("onset_s,impact_speed_mps,kind,drop,peak_amplitude\n", 0), 0u);
  EXPECT_NE(csv.find(",knock,-1,0.300000\n"), std::string::npos) << csv;
}

// RMS frequency of x[from, to): for a sinusoid at f the first difference has (2 sin(pi f / rate))^2
// times its power, so this inverts that relation on the power ratio.
double RmsFrequencyHz(const std::vector<float>& x, double rate, size_t from, size_t to) {
  double power = 0, difference = 0;
  for (size_t i = from + 1; i < to; ++i) {
    power += static_cast<double>(x[i]) * x[i];
    difference += std::pow(static_cast<double>(x[i]) - x[i - 1], 2);
  }
  return rate / std::numbers::pi * std::asin(std::sqrt(difference / power) / 2);
}

TEST(SynthesizeBounces, NonBallEventsSoundDifferentFromBallImpacts) {
  // Each event alone in a file; its spectral centroid (RMS frequency) tells the sounds apart
  // the way a detector's band would: thump < 100 Hz, knock and stray within 0.2-2.5 kHz, the
  // ball on the steel plate far above.
  const auto render = [](std::vector<ImpactSpec> impacts, std::vector<ExtraEvent> extras) {
    SynthesisOptions options = ExplicitImpacts(std::move(impacts));
    options.extra_events = std::move(extras);
    options.duration_s = 1.0;
    return SynthesizeBounces(options).channels[0].samples;
  };
  const auto ball = render({{0.1, 2.0}}, {});
  const auto thump = render({{0.9, 2.0}}, {{SoundEventKind::kThump, 0.1, 0.3}});
  const auto knock = render({{0.9, 2.0}}, {{SoundEventKind::kKnock, 0.1, 0.3}});
  const auto stray = render({{0.9, 2.0}}, {{SoundEventKind::kStray, 0.1, 0.3}});
  const auto window = [](const std::vector<float>& x) {
    return RmsFrequencyHz(x, 48000, 4800, 4800 + 9600);  // 0.1-0.3 s
  };
  EXPECT_LT(window(thump), 100.0);
  EXPECT_GT(window(knock), 200.0);
  EXPECT_LT(window(knock), 2500.0);
  EXPECT_GT(window(stray), 300.0);
  EXPECT_LT(window(stray), 2500.0);
  EXPECT_GT(window(ball), 2500.0);
}

// The limiter runs on the recording as the device's last gain stage: a drop whose first bounce
// peaks at 0.5 with 20 dB of make-up gain leaves no sample above the -1 dBFS ceiling, and the
// truth's onsets are those of the same drop without it.
TEST(SynthesizeBounces, TheLimiterHoldsTheCeilingAndLeavesTheOnsets) {
  SynthesisOptions options = ExplicitImpacts({{0.5, 2.0}, {0.9, 1.5}});
  const auto plain = SynthesizeBounces(options);
  options.limiter = LimiterOptions{};
  options.limiter->gain_db = 20;
  const auto limited = SynthesizeBounces(options);
  const auto& x = limited.channels[0].samples;
  float peak = 0;
  for (const float v : x) peak = std::max(peak, std::fabs(v));
  EXPECT_LE(20 * std::log10(peak), -1.0 + 1e-6);
  EXPECT_GT(20 * std::log10(peak), -1.5);  // driven to it
  EXPECT_EQ(limited.BallImpactOnsetsS(), plain.BallImpactOnsetsS());
}

TEST(SynthesizeBounces, HumDcClippingAndDigitalSilenceAreApplied) {
  SynthesisOptions options = ExplicitImpacts({{0.5, 2.0}});
  options.hum = HumOptions{.frequency_hz = 50.0, .fundamental_dbfs = -30.0, .harmonics_count = 1};
  options.dc_offset = 0.01;
  options.clip_level = 0.2;
  options.leading_digital_silence_s = 0.1;
  const auto recording = SynthesizeBounces(options);
  const auto& x = recording.channels[0].samples;
  for (size_t i = 0; i < 4800; ++i) ASSERT_EQ(x[i], 0.0f) << "sample " << i;
  // Between 0.1 s and the impact: DC plus a 50 Hz sine of amplitude 10^(-30/20) = 0.0316.
  // 0.4 s holds exactly 20 periods, so the mean is the DC and the RMS of the rest A / sqrt(2).
  double mean = 0.0;
  for (size_t i = 4800; i < 24000; ++i) mean += x[i];
  mean /= 19200;
  double ac = 0.0;
  for (size_t i = 4800; i < 24000; ++i) ac += (x[i] - mean) * (x[i] - mean);
  ac = std::sqrt(ac / 19200);
  EXPECT_NEAR(mean, 0.01, 1e-6);                      // float rounding only
  EXPECT_NEAR(ac, 0.0316228 / std::sqrt(2.0), 1e-5);  // idem
  EXPECT_GT(recording.clipped_sample_count[0], 0);
  EXPECT_LE(*std::max_element(x.begin(), x.end()), 0.2f);
  EXPECT_GE(*std::min_element(x.begin(), x.end()), -0.2f);
}

// Complex amplitude of a sinusoid at frequency_hz in x[from, from + count) by correlation (the
// window holds whole periods of both test tones, so they do not leak into each other).
std::complex<double> Tone(const std::vector<float>& x, double rate, double frequency_hz,
                          size_t from, size_t count) {
  std::complex<double> sum = 0.0;
  for (size_t i = from; i < from + count; ++i) {
    const double phase = 2 * std::numbers::pi * frequency_hz * static_cast<double>(i) / rate;
    sum += static_cast<double>(x[i]) * std::polar(1.0, -phase);
  }
  return 2.0 * sum / static_cast<double>(count);
}

TEST(SynthesizeBounces, BandLimitKeepsThePassBandAndRemovesTheStopBand) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 2.0}});
  options.modes = {{2000.0, 10.0, 1.0}, {9000.0, 10.0, 1.0}};  // 10 s decay: steady tones
  const auto open = SynthesizeBounces(options).channels[0].samples;
  options.band_limit_hz = 4000.0;
  const auto limited = SynthesizeBounces(options).channels[0].samples;
  // 0.2-0.3 s: 4800 samples, whole periods of 2 and 9 kHz at 48 kHz.
  const std::complex<double> pass =
      Tone(limited, 48000, 2000, 9600, 4800) / Tone(open, 48000, 2000, 9600, 4800);
  const std::complex<double> stop =
      Tone(limited, 48000, 9000, 9600, 4800) / Tone(open, 48000, 9000, 9600, 4800);
  // Blackman-windowed sinc: pass-band ripple ~0.002 dB, stop band below -74 dB.
  EXPECT_NEAR(20 * std::log10(std::abs(pass)), 0.0, 0.01);
  EXPECT_LT(20 * std::log10(std::abs(stop)), -70.0);
  // Zero phase: the pass-band tone keeps its phase (a one-sample delay would turn it by 0.26 rad).
  EXPECT_NEAR(std::arg(pass), 0.0, 1e-3);
}

TEST(SynthesizeBounces, ModesAboveNyquistAreLeftOutAtLowSampleRates) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 2.0}});
  options.sample_rate_hz = 16000;  // keeps only the modes under 7.2 kHz
  const auto recording = SynthesizeBounces(options);
  EXPECT_GT(PeakIn(recording.channels[0], 0.1, 0.2), 0.05);
  options.modes = {{9000.0, 0.1, 1.0}};
  EXPECT_THROW(SynthesizeBounces(options), ConfigError);
}

// --- Recording chain and contact click -------------------------------------------------------

TEST(SynthesizeBounces, LinearPhaseChainGivesPassBandModesBackInPhaseAndRemovesStopBandModes) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 2.0}});
  options.modes = {{2000.0, 10.0, 1.0}, {9000.0, 10.0, 1.0}};  // 10 s decay: steady tones
  options.duration_s = 0.4;
  const auto open = SynthesizeBounces(options).channels[0].samples;
  options.chain = RecordingChain{};
  const auto chained = SynthesizeBounces(options).channels[0].samples;
  // 0.2-0.3 s, long after the onset. Both tones lie in the pass band at 48 kHz, and the filter
  // is zero-phase, so the chain gives the same samples: up to its ripple (1e-5), the same again
  // in the peak normalisation, and float rounding. A group delay off by one high-rate sample
  // (2.6 us) would turn the 9 kHz tone by 0.15 rad, a difference of ~15 % of its amplitude.
  // Relative to the largest sample over 0.2-0.3 s.
  const auto largest_difference = [](const std::vector<float>& a, const std::vector<float>& b,
                                     double rate) {
    double worst = 0.0, peak = 0.0;
    for (auto i = static_cast<size_t>(0.2 * rate); i < static_cast<size_t>(0.3 * rate); ++i) {
      worst = std::max(worst, std::abs(double{a[i]} - b[i]));
      peak = std::max(peak, std::abs(double{a[i]}));
    }
    return worst / peak;
  };
  EXPECT_LT(largest_difference(open, chained, 48000), 5e-5);

  // At 16 kHz the 9 kHz mode lies above the stop-band edge (8.74 kHz). Without a chain it is
  // left out (it would alias to 7 kHz); with one it is rendered at 384 kHz and the filter
  // removes it 100 dB down: after 0.2 s the file holds the 2 kHz mode alone, in phase. (Only
  // its scale differs: the 9 kHz mode's onset transient passes the filter and lifts the early
  // peak that peak_amplitude is normalised by, so compare after removing the best scale.)
  options.sample_rate_hz = 16000;
  options.chain.reset();
  const auto low_open = SynthesizeBounces(options).channels[0].samples;
  options.chain = RecordingChain{};
  const auto low_chained = SynthesizeBounces(options).channels[0].samples;
  double dot = 0.0, norm = 0.0;
  for (size_t i = 3200; i < 4800; ++i) {
    dot += double{low_open[i]} * low_chained[i];
    norm += double{low_open[i]} * low_open[i];
  }
  std::vector<float> scaled(low_open.size());
  for (size_t i = 0; i < scaled.size(); ++i)
    scaled[i] = static_cast<float>(dot / norm * low_open[i]);
  // Same bound; the 9 kHz residue is 1e-5 of its amplitude, a one-sample-of-384-kHz phase error
  // of the 2 kHz tone 1.6 %.
  EXPECT_LT(largest_difference(scaled, low_chained, 16000), 5e-5);
}

// Energy of x over the samples in [onset_s - window_s, onset_s).
double EnergyBefore(const std::vector<float>& x, double rate, double onset_s, double window_s) {
  const auto first = static_cast<size_t>(std::ceil((onset_s - window_s) * rate));
  double energy = 0.0;
  for (size_t i = first; static_cast<double>(i) / rate < onset_s; ++i) {
    energy += static_cast<double>(x[i]) * x[i];
  }
  return energy;
}

TEST(SynthesizeBounces, LinearPhaseChainPutsEnergyBeforeTheOnsetThatGrowsWithTheImpactLevel) {
  // Each impact alone in its file at 16 kHz (where the filter cuts into the plate's modes, so it
  // rings most), at the same sub-sample position, so that only its level differs; contact click
  // on, as real balls have.
  constexpr double kRate = 16000;
  const double onset_s = 0.1 + 0.37 / kRate;
  const std::vector<double> speeds = {0.5, 1.0, 2.0, 4.0};
  const auto render = [&](double speed, double exponent, std::optional<RecordingChain> chain) {
    SynthesisOptions options = ExplicitImpacts({{onset_s, speed}});
    options.sample_rate_hz = static_cast<int>(kRate);
    options.duration_s = 0.2;
    options.click_gain = 0.2;
    options.contact_duration_speed_exponent = exponent;
    options.chain = chain;
    return SynthesizeBounces(options);
  };
  std::vector<double> rigid, hertz;
  for (double speed : speeds) {
    const auto recording = render(speed, 0.0, RecordingChain{});
    rigid.push_back(EnergyBefore(recording.channels[0].samples, kRate, onset_s, 0.002));
    // A Hertz contact also shortens with speed, which moves the pulse's centre against the
    // sample grid; the filter's ringing depends on that position (none for a centre on a
    // sample: the cutoff is exactly fs / 2), so sum over four positions a quarter sample apart.
    double summed = 0.0;
    for (double quarter : {0.0, 0.25, 0.5, 0.75}) {
      SynthesisOptions options = ExplicitImpacts({{0.1 + quarter / kRate, speed}});
      options.sample_rate_hz = static_cast<int>(kRate);
      options.duration_s = 0.2;
      options.click_gain = 0.2;
      options.chain = RecordingChain{};
      summed += EnergyBefore(SynthesizeBounces(options).channels[0].samples, kRate,
                             0.1 + quarter / kRate, 0.002);
    }
    hertz.push_back(summed);
    // The artefact is not negligible: before contact the file already exceeds 0.4 % of the
    // impact's peak (0.9 % at this position), so a threshold at 1 % of the peak fires early on
    // the louder impacts of a drop.
    double before = 0.0;
    const auto& x = recording.channels[0].samples;
    for (size_t i = 0; static_cast<double>(i) / kRate < onset_s; ++i) {
      before = std::max(before, std::abs(double{x[i]}));
    }
    EXPECT_GT(before, 0.004 * recording.events[0].peak_amplitude) << speed;
  }
  // A rigid contact keeps its pulse shape, and the chain is linear: the energy before the onset
  // scales exactly as the level squared (float rounding, 1e-5).
  for (size_t k = 1; k < speeds.size(); ++k) {
    const double expected = std::pow(speeds[k] / speeds[0], 2);
    EXPECT_NEAR(rigid[k] / rigid[0], expected, 1e-5 * expected);
    // With a Hertz contact (shorter, brighter pulses when faster) it grows too, about as v^2.3.
    EXPECT_GT(hertz[k], 3.0 * hertz[k - 1]);
  }
  // The causal filter and no filter at all leave nothing before contact.
  for (double speed : speeds) {
    const RecordingChain minimum{.phase = AdcFilterPhase::kMinimum};
    EXPECT_EQ(EnergyBefore(render(speed, -0.2, minimum).channels[0].samples, kRate, onset_s, 0.1),
              0.0);
    EXPECT_EQ(
        EnergyBefore(render(speed, -0.2, std::nullopt).channels[0].samples, kRate, onset_s, 0.1),
        0.0);
  }
}

double HalfSine(double t_s, double contact_s) {
  return t_s >= 0.0 && t_s < contact_s ? std::sin(std::numbers::pi * t_s / contact_s) : 0.0;
}

TEST(SynthesizeBounces, ContactClickWithoutAChainIsTheSampledHalfSineWithTheImpactsEchoesAndDelay) {
  SynthesisOptions options = ExplicitImpacts({{0.1000123, 2.0}});
  options.reverb = ReverbOptions{.rt60_s = 0.0, .echoes = {{0.009, -12.0}}};
  options.channels = {ChannelOptions{}, ChannelOptions{.delay_s = 0.00025, .gain_db = -6.0}};
  const auto plain = SynthesizeBounces(options);
  options.click_gain = 0.3;
  const auto clicked = SynthesizeBounces(options);
  const double peak = clicked.events[0].peak_amplitude;
  EXPECT_DOUBLE_EQ(peak, plain.events[0].peak_amplitude);       // the click leaves the truth alone
  const double contact_s = 70e-6 * std::pow(2.0 / 1.98, -0.2);  // Hertz scaling of the default
  const double echo = std::pow(10.0, -12.0 / 20.0);
  for (size_t c = 0; c < 2; ++c) {
    const double gain = c == 0 ? 1.0 : std::pow(10.0, -6.0 / 20.0);
    const double arrival_s = 0.1000123 + (c == 0 ? 0.0 : 0.00025);
    double worst = 0.0;
    int touched = 0;
    for (size_t i = 0; i < clicked.channels[c].samples.size(); ++i) {
      const double t_s = static_cast<double>(i) / 48000;
      const double expected = 0.3 * peak * gain *
                              (HalfSine(t_s - arrival_s, contact_s) +
                               echo * HalfSine(t_s - arrival_s - 0.009, contact_s));
      const double added = double{clicked.channels[c].samples[i]} - plain.channels[c].samples[i];
      worst = std::max(worst, std::abs(added - expected));
      touched += expected != 0.0;
    }
    EXPECT_LT(worst, 1e-6) << c;  // float rounding of the sum
    // A 70 us pulse covers 3-4 samples at 48 kHz, so the sampled click is at the mercy of where
    // the contact falls between them (aliased): that is what the chain is for.
    EXPECT_GE(touched, 4);
    EXPECT_LE(touched, 8);
  }
}

TEST(SynthesizeBounces, ChainPreservesTheAreaOfTheContactClick) {
  // The filter's DC gain is 1 and each of its polyphase branches sums to 1 / M (its response at
  // multiples of fs lies in the stop band): the file holds the click's impulse, the sum of its
  // high-rate samples over the high rate, to ~M x 1e-5.
  SynthesisOptions options = ExplicitImpacts({{0.1000123, 2.0}});
  options.duration_s = 0.2;
  options.chain = RecordingChain{};
  const auto plain = SynthesizeBounces(options);
  options.click_gain = 0.2;
  const auto clicked = SynthesizeBounces(options);
  ASSERT_TRUE(clicked.chain.has_value());
  const double high_rate = clicked.chain->high_rate_hz;
  const double contact_s = 70e-6 * std::pow(2.0 / 1.98, -0.2);
  const double peak = 0.2 * clicked.events[0].peak_amplitude;
  double impulse = 0.0;
  for (auto j = static_cast<std::int64_t>(0.1 * high_rate); j < 0.1001 * high_rate; ++j) {
    impulse += peak * HalfSine(static_cast<double>(j) / high_rate - 0.1000123, contact_s);
  }
  impulse /= high_rate;
  double file_impulse = 0.0;
  for (size_t i = 0; i < plain.channels[0].samples.size(); ++i) {
    file_impulse += double{clicked.channels[0].samples[i]} - plain.channels[0].samples[i];
  }
  file_impulse /= 48000;
  EXPECT_NEAR(file_impulse / impulse, 1.0, 2e-4);
  // Which is the half-sine's area, 2 tau / pi x peak, to its sampling at 384 kHz (~0.1 %).
  EXPECT_NEAR(impulse / (2 * contact_s / std::numbers::pi * peak), 1.0, 2e-3);
}

TEST(SynthesizeBounces, ChainKeepsTheTruthThePeakAmplitudeAndTheSnrDefinition) {
  SynthesisOptions options = ExplicitImpacts({{0.1, 1.98}, {0.6, 1.2}});
  options.peak_amplitude = 0.3;
  const auto plain = SynthesizeBounces(options);
  options.chain = RecordingChain{};
  const auto chained = SynthesizeBounces(options);
  ASSERT_EQ(chained.events.size(), plain.events.size());
  for (size_t i = 0; i < plain.events.size(); ++i) {
    EXPECT_EQ(chained.events[i].onset_s, plain.events[i].onset_s);
    EXPECT_EQ(chained.events[i].peak_amplitude, plain.events[i].peak_amplitude);
  }
  // With a chain, peak_amplitude is the sampled peak of what reaches the file (onset on a
  // sample, as it is normalised): float rounding.
  EXPECT_NEAR(PeakIn(chained.channels[0], 0.1, 0.15), 0.3, 1e-6);
  // The SNR's signal power is the direct sound as recorded, click and chain included; 0.01 dB as
  // in MeasuredSnrMatchesTheRequestForWhiteAndPinkNoise.
  SynthesisOptions noisy = ExplicitImpacts({{0.2, 1.0}});
  noisy.noise = NoiseOptions{.snr_db = 10.0};
  noisy.click_gain = 0.3;
  EXPECT_NEAR(MeasuredSnrDb(noisy, 0.2), 10.0, 0.01);
  noisy.chain = RecordingChain{};
  EXPECT_NEAR(MeasuredSnrDb(noisy, 0.2), 10.0, 0.01);
  noisy.sample_rate_hz = 16000;
  noisy.chain = RecordingChain{.phase = AdcFilterPhase::kMinimum};
  EXPECT_NEAR(MeasuredSnrDb(noisy, 0.2), 10.0, 0.01);
  // And the same options render the same samples.
  EXPECT_EQ(SynthesizeBounces(noisy).channels[0].samples,
            SynthesizeBounces(noisy).channels[0].samples);
}

TEST(SynthesizeBounces, TruthCsvDescribesTheChainAndClickInCommentsReadersSkip) {
  SynthesisOptions options;
  const std::string plain = TruthCsv(SynthesizeBounces(options));
  EXPECT_EQ(plain.rfind("onset_s,", 0), 0u);  // unchanged without them
  options.chain = RecordingChain{};
  options.click_gain = 0.2;
  const auto recording = SynthesizeBounces(options);
  ASSERT_TRUE(recording.chain.has_value());
  EXPECT_EQ(recording.chain->chain.oversampling, 8);  // resolved from automatic
  EXPECT_GE(recording.chain->stopband_attenuation_db, 100.0);
  const std::string csv = TruthCsv(recording);
  EXPECT_EQ(csv.rfind("# recording chain: linear-phase anti-aliasing FIR, ", 0), 0u) << csv;
  EXPECT_NE(csv.find("# contact click: "), std::string::npos) << csv;
  const auto impacts = ParseImpactCsv(csv, "truth.csv");
  const auto onsets = recording.BallImpactOnsetsS();
  ASSERT_EQ(impacts.size(), onsets.size());
  for (size_t i = 0; i < onsets.size(); ++i) EXPECT_NEAR(impacts[i].onset_s, onsets[i], 5e-10);
}

void ExpectConfigErrorNaming(const SynthesisOptions& options, const std::string& name) {
  try {
    SynthesizeBounces(options);
    FAIL() << "expected ConfigError naming " << name;
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(SynthesizeBounces, InvalidOptionsGiveOneLineErrorsNamingTheOption) {
  SynthesisOptions options;
  options.sample_rate_hz = 4000;
  ExpectConfigErrorNaming(options, "sample_rate_hz = 4000 is outside [8000, 384000]");
  options = {};
  options.drop.restitution.constant = 1.2;
  ExpectConfigErrorNaming(options, "drop.restitution.constant");
  options = {};
  options.drop.restitution.callback = [](double v) { return v > 1.0 ? 1.5 : 0.5; };
  ExpectConfigErrorNaming(options, "drop.restitution gives e = 1.5");
  options = {};
  options.contact_duration_s = -1e-6;
  ExpectConfigErrorNaming(options, "contact_duration_s");
  options = {};
  options.noise = NoiseOptions{.snr_db = std::nan("")};
  ExpectConfigErrorNaming(options, "noise.snr_db");
  options = {};
  options.channels.clear();
  ExpectConfigErrorNaming(options, "channels");
  options = {};
  options.extra_events = {{SoundEventKind::kBallImpact, 0.1, 0.1}};
  ExpectConfigErrorNaming(options, "extra_events[0].kind");
  options = {};
  options.leading_digital_silence_s = 1.0;
  ExpectConfigErrorNaming(options, "leading_digital_silence_s");
  RectangularPlate plate;
  plate.thickness_m = std::nan("");
  EXPECT_THROW(RectangularPlateModes(plate), ConfigError);
  plate = {};
  plate.thickness_m = 1e-6;  // a foil: millions of modes
  EXPECT_THROW(RectangularPlateModes(plate), ConfigError);
  options = {};
  options.band_limit_hz = 30000.0;
  ExpectConfigErrorNaming(options, "band_limit_hz");
  options = ExplicitImpacts({{0.5, 2.0}});
  options.limiter = LimiterOptions{};
  options.limiter->gain_db = 80;
  ExpectConfigErrorNaming(options, "limiter.gain_db = 80 is outside [0, 60]");
  options = {};
  options.clip_level = 1.5;
  ExpectConfigErrorNaming(options, "clip_level");
  options = {};
  options.chain = RecordingChain{.oversampling = 1};
  ExpectConfigErrorNaming(options, "chain.oversampling = 1 leaves nothing to decimate");
  options.chain = RecordingChain{.stopband_edge_fraction = 0.6};
  ExpectConfigErrorNaming(options, "chain.stopband_edge_fraction = 0.6");
  options.chain = RecordingChain{.stopband_attenuation_db = 200.0};
  ExpectConfigErrorNaming(options, "chain.stopband_attenuation_db");
  options.chain = RecordingChain{};
  options.duration_s = 400.0;  // 154 million samples at 384 kHz
  ExpectConfigErrorNaming(options, "high-rate samples per channel");
  options = {};
  options.click_gain = std::nan("");
  ExpectConfigErrorNaming(options, "click_gain");
}

}  // namespace
}  // namespace bouncecal::audio
