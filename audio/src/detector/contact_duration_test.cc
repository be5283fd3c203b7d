#include "detector/contact_duration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "bouncecal/audio/response_timing.h"
#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {
namespace {

// A steel ball bouncing on an anvil-like plate (e = 0.8 from 0.35 m: 13 bounces, speeds 2.6 to
// 0.3 m/s, so the last contact lasts 1.7x the first), recorded through a linear-phase ADC chain
// (the pulse is band-limited as a real converter does, not aliased), 35 dB SNR, a small room.
SynthesizedRecording AnvilDrop(int seed, double contact_duration_s) {
  SynthesisOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  options.drop.drop_height_m = 0.35;
  options.drop.restitution.constant = 0.8;
  options.drop.min_flight_s = 0.03;
  options.contact_duration_s = contact_duration_s;
  options.chain = RecordingChain{};
  ReverbOptions reverb;
  reverb.rt60_s = 0.3;
  options.reverb = reverb;
  NoiseOptions noise;
  noise.snr_db = 35;
  options.noise = noise;
  return SynthesizeBounces(options);
}

// Retimes the drop's detection as DetectImpactsInFile does a PCM file of its rate.
ResponseTimingSummary RetimeAsItsFile(DetectionResult& detection,
                                      const SynthesizedRecording& drop) {
  RecordingInfo info;
  info.sample_rate_hz = drop.channels[0].sample_rate_hz;
  return RetimeFromResponses(detection, drop.channels[0].samples, 0, ResponseTimingFor(info));
}

double TrueDuration(const SynthesisOptions& options, double speed_mps) {
  return options.contact_duration_s *
         std::pow(speed_mps / options.reference_speed_mps, options.contact_duration_speed_exponent);
}

// The onset errors of the impacts, less their median (only relative times matter).
std::vector<double> RelativeErrors(const DetectionResult& detection,
                                   const std::vector<double>& truth) {
  std::vector<double> errors;
  for (double t : truth) {
    const auto nearest = std::min_element(
        detection.impacts.begin(), detection.impacts.end(), [&](const Impact& a, const Impact& b) {
          return std::fabs(a.onset_s - t) < std::fabs(b.onset_s - t);
        });
    if (nearest != detection.impacts.end() && std::fabs(nearest->onset_s - t) < 1e-3) {
      errors.push_back(nearest->onset_s - t);
    }
  }
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  for (double& e : errors) e -= median;
  return errors;
}

// 30 dB referred to the weakest impact, as the benches' drops are recorded.
NoiseOptions ThirtyDbOverTheWeakestImpact() {
  NoiseOptions noise;
  noise.snr_db = 30;
  noise.reference = SnrReference::kWeakestImpact;
  return noise;
}

// A drop synthesised, detected and retimed as its file would be.
struct RetimedDrop {
  SynthesizedRecording drop;
  DetectionResult detection;
  ResponseTimingSummary summary;
};

RetimedDrop SynthesizeAndRetime(const SynthesisOptions& options) {
  RetimedDrop result{SynthesizeBounces(options), {}, {}};
  result.detection = DetectImpacts(result.drop.channels[0]);
  result.summary = RetimeAsItsFile(result.detection, result.drop);
  return result;
}

// The drift's signature: the mean relative error of the last four impacts less that of the
// first four (late impacts, with longer contacts, later than early ones where uncorrected).
double LateMinusEarly(const std::vector<double>& errors) {
  double early = 0;
  double late = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    early += errors[k] / 4;
    late += errors[errors.size() - 1 - k] / 4;
  }
  return late - early;
}

// The drop's first ball impact: the loudest, the template.
const SynthesizedEvent& FirstBallImpact(const SynthesizedRecording& drop) {
  return *std::find_if(drop.events.begin(), drop.events.end(), [](const SynthesizedEvent& e) {
    return e.kind == SoundEventKind::kBallImpact;
  });
}

// The template's contact duration is recovered from the responses' spectra alone, for a hard
// and a softer contact.
TEST(ContactDurations, TheTemplatesDurationIsRecoveredFromTheSpectra) {
  for (double duration : {70e-6, 150e-6}) {
    for (int seed = 1; seed <= 2; ++seed) {
      const auto drop = AnvilDrop(seed, duration);
      auto detection = DetectImpacts(drop.channels[0]);
      const auto summary = RetimeAsItsFile(detection, drop);
      ASSERT_GT(summary.contact_duration_s, 0) << duration << " seed " << seed;
      // The template is the loudest impact: the first, at the release speed.
      const auto& first = FirstBallImpact(drop);
      SynthesisOptions defaults;
      defaults.contact_duration_s = duration;
      const double truth = TrueDuration(defaults, first.impact_speed_mps);
      // 20 %: the estimate's own jackknife sd here is 3-6 %, and a real pulse's shape (Hertz's
      // is more peaked than the half-sine the estimate assumes) moves it by ~10 %.
      EXPECT_NEAR(std::log(summary.contact_duration_s / truth), 0.0, 0.2)
          << duration * 1e6 << " us, seed " << seed << ": estimated "
          << summary.contact_duration_s * 1e6 << " us";
      EXPECT_LT(summary.contact_duration_log_sd, 0.2);
    }
  }
}

// Aligned to the loudest impact's response, later impacts lock on their force's centroid, which
// moves later by half the growth of the contact (+12 us at the 8th bounce of a 66 us contact);
// corrected, the onsets of a WAV keep no drift that the speed-trend test could read as physics.
TEST(ContactDurations, RetimedOnsetsOfAWavDoNotDriftWithTheContactsDuration) {
  for (int seed = 1; seed <= 3; ++seed) {
    const auto drop = AnvilDrop(seed, 70e-6);
    const auto truth = drop.BallImpactOnsetsS();
    auto detection = DetectImpacts(drop.channels[0]);
    const auto summary = RetimeAsItsFile(detection, drop);
    ASSERT_GT(summary.aligned, 8);
    const auto errors = RelativeErrors(detection, truth);
    ASSERT_GE(errors.size(), 10u);
    // Uncorrected, the last four average 13-14 us after the first four; corrected, within 3 us
    // (a seventh of a sample, the alignments' own scatter here is ~1 us).
    const double drift = LateMinusEarly(errors);
    EXPECT_LT(std::fabs(drift), 3e-6)
        << "seed " << seed << ": late - early " << drift * 1e6 << " us";
  }
}

// Below 20 kHz the band ends before a short contact's spectrum bends: no duration is claimed, and
// the onsets keep the uncorrected alignment (such files are retimed for their unreliable first
// lobe; contact_duration.cc has the measurement behind the limit).
TEST(ContactDurations, BelowTwentyKilohertzAShortContactClaimsNone) {
  // A ping-pong ball on a counter, whose fit at 16 kHz would claim 116 us (jackknife sd 19 %)
  // for its 47 us contact.
  SynthesisOptions options;
  options.sample_rate_hz = 16000;
  options.modes = CounterTopModes();
  options.contact_duration_s = 50e-6;
  options.drop.drop_height_m = 0.3;
  options.drop.restitution.constant = 0.9;
  ReverbOptions reverb;
  reverb.rt60_s = 0.2;
  options.reverb = reverb;
  options.noise = ThirtyDbOverTheWeakestImpact();
  const auto retimed = SynthesizeAndRetime(options);
  EXPECT_GT(retimed.summary.aligned, 3);
  EXPECT_EQ(retimed.summary.contact_duration_s, 0.0);
}

// A fit at 16 kHz can also land on a long duration for a short contact: codec_timing_bench's
// ping-pong on a counter (seeds 13 and 16) read 954 and 999 us for its 50 us contact, jackknife
// sd 1-19 %. Such a duration puts the response's spectrum's first zero at 1.5 kHz, where 99.6 %
// of the template's power lies above it; a true contact that long leaves a few percent there.
TEST(ContactDurations, AtSixteenKilohertzADurationTheResponseContradictsIsNotClaimed) {
  for (int seed : {13, 16}) {
    SynthesisOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.sample_rate_hz = 16000;
    options.peak_amplitude = 0.2 + 0.5 * std::fmod(0.5698402910 * seed, 1.0);
    options.drop.min_flight_s = 0.03;
    options.modes = CounterTopModes();
    options.contact_duration_s = 50e-6;
    options.drop.drop_height_m = 0.2 + 0.2 * std::fmod(0.6180339887 * seed, 1.0);
    options.drop.restitution.constant = 0.85 + 0.1 * std::fmod(0.7548776662 * seed, 1.0);
    options.drop.max_impacts_per_drop = 25;
    ReverbOptions reverb;
    reverb.rt60_s = 0.2;
    reverb.echoes = {{0.009, -12.0}};
    options.reverb = reverb;
    options.noise = ThirtyDbOverTheWeakestImpact();
    const auto retimed = SynthesizeAndRetime(options);
    EXPECT_EQ(retimed.summary.contact_duration_s, 0.0)
        << "seed " << seed << ": claimed " << retimed.summary.contact_duration_s * 1e6 << " us";
  }
}

// A soft ball's contact (0.8 ms) bends its spectrum well inside a 16 kHz file's band, so there
// too its duration is estimated and the aligned onsets are moved back to the start of contact.
// Uncorrected, a rubber ball on a table drifted by 150-200 us from its first four bounces to its
// last four (each later contact lasts longer, and the alignment locks on its centroid), at stated
// sigmas of 30-50 us (detector_accuracy_bench's "rubber on table 16k": 81 % within 2 sigmas).
TEST(ContactDurations, AtSixteenKilohertzASoftContactIsResolvedAndItsDriftRemoved) {
  for (int seed = 1; seed <= 3; ++seed) {
    SynthesisOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.sample_rate_hz = 16000;
    options.modes = TableTopModes();
    options.contact_duration_s = 800e-6;
    options.drop.drop_height_m = 0.5;
    options.drop.restitution.constant = 0.77;
    options.drop.min_flight_s = 0.03;
    options.chain = RecordingChain{};
    options.click_gain = 0.15;
    options.amplitude_speed_exponent = 1.5;
    ReverbOptions reverb;
    reverb.rt60_s = 0.3;
    options.reverb = reverb;
    options.noise = ThirtyDbOverTheWeakestImpact();
    const auto retimed = SynthesizeAndRetime(options);
    const auto& summary = retimed.summary;
    ASSERT_GT(summary.contact_duration_s, 0) << "seed " << seed;
    const auto& first = FirstBallImpact(retimed.drop);
    // 50 %: at 16 kHz the estimate reads 0.49-0.62 ms for the first bounce's 0.73 ms (the table's
    // modes above the band's top are gone, and with them part of the spectrum's bend).
    EXPECT_NEAR(
        std::log(summary.contact_duration_s / TrueDuration(options, first.impact_speed_mps)), 0.0,
        0.5)
        << "seed " << seed << ": estimated " << summary.contact_duration_s * 1e6 << " us";
    const auto errors = RelativeErrors(retimed.detection, retimed.drop.BallImpactOnsetsS());
    ASSERT_GE(errors.size(), 8u);
    // Uncorrected 153-165 us; corrected -77..+60 us here (the estimate's error above, and the
    // ringing the tail's bounces are timed in). 100 us: clearly under the drift left alone.
    const double drift = LateMinusEarly(errors);
    EXPECT_LT(std::fabs(drift), 100e-6)
        << "seed " << seed << ": late - early " << drift * 1e6 << " us";
  }
}

// The duration law reads each impact's speed ratio from its impulse ratio (J = m (1 + e) v), which
// the spectra give as the ratio of their low-frequency levels. A recording whose loudness grows
// faster than the impulse (this rubber ball's, as v^1.5: the spectra read v^1.5 for v) is
// corrected by 1.5 times its drift, and no spectrum tells the two apart, so a third of each shift
// is stated with it. detector_accuracy_bench's rubber on a table, seeds 1-12 at 48 kHz: of the
// aligned onsets relative to their drop's median, 111 of 123 (90 %) lay within two stated sigmas
// without that share (late bounces over-corrected by up to 40 us at stated 10-20 us), 122 (99 %)
// with it. 93 %: between the two, a binomial sd (2 %) under 95 %.
TEST(ContactDurations, AShiftTheLoudnessLawCouldOverstateIsStatedWithIt) {
  int onsets = 0;
  int within = 0;
  for (int seed = 1; seed <= 12; ++seed) {
    SynthesisOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.modes = TableTopModes();
    options.contact_duration_s = 800e-6;
    options.drop.drop_height_m = 0.5;
    options.drop.restitution.constant = 0.74 + 0.06 * std::fmod(0.7548776662 * seed, 1.0);
    options.chain = RecordingChain{};
    options.click_gain = 0.15;
    options.amplitude_speed_exponent = 1.5;
    ReverbOptions reverb;
    reverb.rt60_s = 0.3;
    reverb.direct_to_reverberant_db = 4;
    reverb.echoes = {{0.0015, -14.0}, {0.006, -10.0}};
    options.reverb = reverb;
    options.noise = ThirtyDbOverTheWeakestImpact();
    const auto retimed = SynthesizeAndRetime(options);
    ASSERT_GT(retimed.summary.contact_duration_s, 0) << "seed " << seed;
    std::vector<std::pair<double, double>> aligned;  // (error, stated sigma)
    for (double t : retimed.drop.BallImpactOnsetsS()) {
      for (const Impact& impact : retimed.detection.impacts) {
        if (impact.timed_from_response && std::fabs(impact.onset_s - t) < 1e-3) {
          aligned.emplace_back(impact.onset_s - t, impact.onset_uncertainty_s);
        }
      }
    }
    ASSERT_GE(aligned.size(), 8u) << "seed " << seed;
    std::vector<double> sorted;
    for (const auto& [error, sigma] : aligned) sorted.push_back(error);
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    for (const auto& [error, sigma] : aligned) {
      ++onsets;
      within += std::fabs(error - median) <= 2 * sigma ? 1 : 0;
    }
  }
  std::printf("aligned onsets within 2 stated sigmas: %d of %d\n", within, onsets);
  EXPECT_GE(within, 0.93 * onsets) << within << " of " << onsets;
}

}  // namespace
}  // namespace bouncecal::audio
