#include "detector/ringing_residual.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "dsp/real_fft.h"
#include "synth/band_limit.h"

namespace bouncecal::audio {
namespace {

constexpr int kRate = 48000;
// The detector counts a novelty of 0.6 dB as a full rise (impact_detector.cc).
constexpr double kDetectorThresholdDb = 0.6;

// Plate-like ringing from t = 0: two modes 80 Hz apart that share one ~190 Hz bin and beat with
// a 12.5 ms period (the case the earlier one-tone-per-bin predictor failed on), and a third,
// louder one (decays 0.25, 0.2 and 0.12 s).
float Ringing(int i) {
  const double t = static_cast<double>(i) / kRate;
  const double two_pi = 2 * std::numbers::pi;
  return static_cast<float>(0.4 * std::exp(-t / 0.25) * std::sin(two_pi * 1250 * t) +
                            0.3 * std::exp(-t / 0.2) * std::sin(two_pi * 1330 * t + 1.0) +
                            0.5 * std::exp(-t / 0.12) * std::sin(two_pi * 4130 * t));
}

struct Frame {
  double end_s;
  double novelty_db;
  double noise_power;
};

std::vector<Frame> Analyse(const std::vector<float>& x) {
  RingingResidual residual(kRate, 300.0, 0.0);
  std::vector<Frame> frames;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (residual.Push(x[i]) && residual.valid()) {
      frames.push_back(
          {static_cast<double>(i + 1) / kRate, residual.novelty_db(), residual.noise_power()});
    }
  }
  return frames;
}

std::vector<float> RingingWithNoise(double noise_rms) {
  std::vector<float> x(kRate / 5);
  std::mt19937 random(5);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_rms));
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = Ringing(static_cast<int>(i)) + noise(random);
  return x;
}

TEST(RingingResidual, BeatingModesGiveNoNovelty) {
  const auto frames = Analyse(RingingWithNoise(1e-4));
  ASSERT_GT(frames.size(), 80u);
  // A decaying bin, even one where two modes beat, never rises above the peaks of its own
  // beats within the 20 ms lookback; only the noise bins between the modes fluctuate (a few
  // tenths of a dB averaged over the band). Half the detector's threshold bounds it.
  double worst = 0;
  for (const auto& frame : frames) worst = std::max(worst, frame.novelty_db);
  EXPECT_LT(worst, 0.5 * kDetectorThresholdDb);
}

TEST(RingingResidual, AWeakClickInsideLoudRingingStandsOut) {
  auto x = RingingWithNoise(1e-4);
  // A two-sample click at 0.1 s, 18 dB below the ringing's amplitude: no band-energy rise would
  // show it, but it lifts every bin where the ringing is only noise.
  const std::size_t at = kRate / 10;
  x[at] += 0.05f;
  x[at + 1] -= 0.035f;
  double before = 0;
  double after = 0;
  for (const auto& frame : Analyse(x)) {
    const double click_s = static_cast<double>(at) / kRate;
    if (frame.end_s < click_s) before = std::max(before, frame.novelty_db);
    if (frame.end_s > click_s && frame.end_s < click_s + 6e-3) {
      after = std::max(after, frame.novelty_db);
    }
  }
  // It must clear the detector's threshold with margin (a factor 2) where the ringing alone
  // stays below half of it.
  EXPECT_GT(after, 2 * kDetectorThresholdDb);
  EXPECT_LT(before, 0.5 * kDetectorThresholdDb);
}

TEST(RingingResidual, NoisePowerIsReadUnderTheRinging) {
  const double noise_rms = 1e-3;  // 50 dB under the ringing's amplitude
  const auto frames = Analyse(RingingWithNoise(noise_rms));
  ASSERT_GT(frames.size(), 80u);
  // The lower quartile of ~125 bins of noise scatters by ~1 dB frame to frame, and the Hann side
  // lobes of modes 50 dB above the noise lift many bins (measured up to +3.4 dB while they are
  // loudest). So -2 dB below and +4 dB above bound it, where the ringing itself is 40-50 dB
  // higher; an estimate biased high only makes the SNR gate stricter.
  for (const auto& frame : frames) {
    const double error_db = 10 * std::log10(frame.noise_power / (noise_rms * noise_rms));
    EXPECT_GT(error_db, -2.0) << frame.end_s;
    EXPECT_LT(error_db, 4.0) << frame.end_s;
  }
}

// The content edge is where a codec or phone path cut the recording's spectrum: white noise 54 dB
// under the plate's loudest mode fills the band to Nyquist; the same at 22.05 kHz through a
// low-pass at 6.3 kHz (a 630 Hz transition band and a -74 dB stop band, BandLimit, as the
// random-impairment sweep's files that timed impacts early in the 6 kHz band) ends between the
// transition band's middle and three bins (172 Hz each: the window's main lobe and the noise's
// own maxima) past its end (measured 7.06 kHz); and silence leaves the band's edge. (With the
// noise 74 dB under the modes, their Hann side lobes reach past the cut to within 30 dB of the
// noise and the edge reads 9.1 kHz: too high, the side that changes nothing.)
TEST(RingingResidual, ContentEdgeIsWhereTheRecordingsSpectrumWasCut) {
  constexpr int kLowRate = 22050;
  const auto edge_of = [](const std::vector<float>& x, int rate) {
    RingingResidual residual(rate, 300.0, 0.0);
    for (float sample : x) residual.Push(sample);
    return residual.content_edge_hz();
  };
  auto x = RingingWithNoise(1e-3);
  EXPECT_GE(edge_of(x, kRate), 0.97 * kRate / 2);
  // The same samples read at 22.05 kHz: modes at 574, 611 and 1898 Hz.
  EXPECT_GE(edge_of(x, kLowRate), 0.97 * kLowRate / 2);
  BandLimit(6300.0, 630.0, kLowRate, x);
  const double edge_hz = edge_of(x, kLowRate);
  EXPECT_GT(edge_hz, 6300.0);
  EXPECT_LT(edge_hz, 6300.0 + 315.0 + 3 * 172.0);
  EXPECT_GE(edge_of(std::vector<float>(kRate / 10, 0.0f), kRate), 0.97 * kRate / 2);
}

// A transform codec's quiet stretch: white noise coded frame by frame (1024 samples, half
// overlapping, sine windows), where the codec narrows its bandwidth: above 55 % of Nyquist it
// leaves each 16-bin band of each frame either empty or at -80 dB of the noise (the residues that
// put the shared Palla-audio.wav's bins 60-160 dB under its noise in its MP3 and AAC copies),
// after a loud broadband click, coded in full, that made every bin hold content once.
std::vector<float> CodedNoiseWithACutThatComesAndGoes() {
  constexpr int kFrame = 1024;
  constexpr std::size_t kBandBins = 16;
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 1e-3);
  std::bernoulli_distribution residue(0.5);
  std::vector<double> input(kRate), coded(kRate, 0.0);
  for (double& x : input) x = noise(random);
  const std::size_t click = kRate / 20;
  input[click] += 0.5;
  RealFftDouble fft(kFrame);
  std::vector<double> window(kFrame);
  for (int i = 0; i < kFrame; ++i) window[i] = std::sin(std::numbers::pi * (i + 0.5) / kFrame);
  const std::size_t cut = static_cast<std::size_t>(0.55 * (kFrame / 2 + 1));
  for (std::size_t start = 0; start + kFrame <= input.size(); start += kFrame / 2) {
    for (int i = 0; i < kFrame; ++i) fft.real()[i] = input[start + i] * window[i];
    fft.Forward();
    const auto spectrum = fft.spectrum();
    // A frame that holds the click is coded in full.
    const bool loud = start <= click && click < start + kFrame;
    for (std::size_t band = loud ? spectrum.size() : cut; band < spectrum.size();
         band += kBandBins) {
      const double gain = residue(random) ? 1e-4 : 0.0;
      for (std::size_t k = band; k < std::min(spectrum.size(), band + kBandBins); ++k) {
        spectrum[k] *= gain;
      }
    }
    fft.Inverse();
    for (int i = 0; i < kFrame; ++i) coded[start + i] += fft.real()[i] * window[i] / kFrame;
  }
  return std::vector<float>(coded.begin(), coded.end());
}

TEST(RingingResidual, ACodecsEmptiedBandsAreNoNovelty) {
  const auto frames = Analyse(CodedNoiseWithACutThatComesAndGoes());
  // Bins that stay 20 dB or more under the noise rise from nothing, whatever their residues do:
  // over the quiet stretch the novelty stays under the detector's threshold as in plain noise
  // (0.2-0.3 dB), where the residues alone lifted 4-12 % of the frames above it (the codec's
  // copies of real recordings: 7-11 %, against their WAV's 0.3 %).
  int above = 0, counted = 0;
  for (const auto& frame : frames) {
    if (frame.end_s < 0.2 || frame.end_s > 0.98) continue;
    ++counted;
    above += frame.novelty_db > kDetectorThresholdDb ? 1 : 0;
  }
  ASSERT_GT(counted, 400);
  EXPECT_LE(above, counted / 200);
}

TEST(RingingResidual, NoisePowerIsReadBesideACodecsEmptiedBands) {
  const auto frames = Analyse(CodedNoiseWithACutThatComesAndGoes());
  // Nearly half the band's bins empty or 80 dB down put the lower quartile of all bins among
  // them; the noise is the quartile of the others, as in NoisePowerIsReadUnderTheRinging (the
  // sine windows' overlap-add keeps the coded noise's level, and half the band is coded: -2 dB
  // to +4 dB).
  for (const auto& frame : frames) {
    // The last 20 ms hold only half a coded frame.
    if (frame.end_s < 0.2 || frame.end_s > 0.98) continue;
    const double error_db = 10 * std::log10(frame.noise_power / (1e-3 * 1e-3));
    EXPECT_GT(error_db, -4.0) << frame.end_s;
    EXPECT_LT(error_db, 4.0) << frame.end_s;
  }
}

// A room's loud reverberation after a quiet second, as a transform codec codes it: noise 40 dB
// over the quiet one (frames of 1024 samples, half overlapping, sine windows), in which the codec
// leaves out a top band of 64 of its bins (8 of the residual's) that the loud noise masks, and
// codes it again, 30 dB under the noise, in a third of its frames at random (the detector suite's
// reverb_strong as MP3 128k: bins 17-20 kHz, 35-46 dB under the median bin, rising by 20-31 dB).
// With click_at_s > 0, a click 20 dB over the noise there, coded in full.
std::vector<float> ReverberationWithABandCodedNowAndThen(double click_at_s) {
  constexpr int kFrame = 1024;
  constexpr double kQuietRms = 1e-4;
  constexpr double kLoudRms = 1e-2;
  std::mt19937 random(17);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::bernoulli_distribution coded_now(1.0 / 3.0);
  const std::size_t loud_from = kRate;
  std::vector<double> input(3 * kRate / 2), coded(input.size(), 0.0);
  for (std::size_t i = 0; i < input.size(); ++i) {
    input[i] = (i < loud_from ? kQuietRms : kLoudRms) * noise(random);
  }
  const auto click = static_cast<std::size_t>(click_at_s * kRate);
  if (click_at_s > 0) input[click] += 10 * kLoudRms * std::sqrt(kFrame);
  RealFftDouble fft(kFrame);
  std::vector<double> window(kFrame);
  for (int i = 0; i < kFrame; ++i) window[i] = std::sin(std::numbers::pi * (i + 0.5) / kFrame);
  const std::size_t band_from = 400, band_to = 464;
  for (std::size_t start = 0; start + kFrame <= input.size(); start += kFrame / 2) {
    for (int i = 0; i < kFrame; ++i) fft.real()[i] = input[start + i] * window[i];
    fft.Forward();
    const auto spectrum = fft.spectrum();
    const bool loud = start >= loud_from;
    const bool holds_click = click_at_s > 0 && start <= click && click < start + kFrame;
    if (loud && !holds_click) {
      const double gain = coded_now(random) ? std::pow(10.0, -30.0 / 20) : 1e-4;
      for (std::size_t k = band_from; k < band_to; ++k) spectrum[k] *= gain;
    }
    fft.Inverse();
    for (int i = 0; i < kFrame; ++i) coded[start + i] += fft.real()[i] * window[i] / kFrame;
  }
  return std::vector<float>(coded.begin(), coded.end());
}

struct CodedFrame {
  double end_s;
  double novelty_db;
  double codec_novelty_db;
};

std::vector<CodedFrame> AnalyseCoded(const std::vector<float>& x, bool transform_coded) {
  RingingResidual residual(kRate, 300.0, 0.0);
  residual.set_transform_coded(transform_coded);
  std::vector<CodedFrame> frames;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (residual.Push(x[i]) && residual.valid()) {
      frames.push_back({static_cast<double>(i + 1) / kRate, residual.novelty_db(),
                        residual.CodecNoveltyDb(residual.latest_frame())});
    }
  }
  return frames;
}

TEST(RingingResidual, ABandACodecCodesNowAndThenInALoudTailIsNoNoveltyInACodedFile) {
  const auto frames = AnalyseCoded(ReverberationWithABandCodedNowAndThen(0), true);
  // Over the reverberation (after its first 20 ms, the lookback), NoveltyDb counts the band's
  // rises from the codec's empty frames: with the noise's floor (its minimum over 2 s, the quiet
  // second's, 40 dB down) the 8 bins rise by up to ~40 dB over the band's 127 bins, and 19 of 254
  // frames pass the detector's threshold (up to 1.24 dB). CodecNoveltyDb counts them only from
  // 20 dB under the median bin, which the band, coded 30 dB under the noise, never reaches: what
  // is left is plain noise's novelty (0.15 dB on average, at most 0.45 dB here), and no frame
  // passes.
  int plain_above = 0, codec_above = 0, counted = 0;
  for (const auto& frame : frames) {
    if (frame.end_s < 1.03 || frame.end_s > 1.48) continue;
    ++counted;
    plain_above += frame.novelty_db > kDetectorThresholdDb ? 1 : 0;
    codec_above += frame.codec_novelty_db > kDetectorThresholdDb ? 1 : 0;
  }
  ASSERT_GT(counted, 200);
  EXPECT_GT(plain_above, counted / 20);
  EXPECT_EQ(codec_above, 0);
}

TEST(RingingResidual, AClickInACodedLoudTailKeepsItsCodecNovelty) {
  const double click_s = 1.25;
  const auto frames = AnalyseCoded(ReverberationWithABandCodedNowAndThen(click_s), true);
  // A broadband sound rises in every bin, not only in the band the codec codes now and then: the
  // floor 20 dB under the median bin takes nothing from it (the frames whose window holds the
  // click: 20 dB over the noise in one sample, spread over the window).
  double codec_at_click = 0;
  for (const auto& frame : frames) {
    if (frame.end_s > click_s && frame.end_s < click_s + 0.006) {
      codec_at_click = std::max(codec_at_click, frame.codec_novelty_db);
    }
  }
  EXPECT_GT(codec_at_click, 2 * kDetectorThresholdDb);
}

TEST(RingingResidual, WithoutACodecTheCodecNoveltyIsTheNovelty) {
  for (const auto& frame : AnalyseCoded(ReverberationWithABandCodedNowAndThen(1.25), false)) {
    EXPECT_EQ(frame.codec_novelty_db, frame.novelty_db) << frame.end_s;
  }
}

TEST(RingingResidual, SilenceGivesNoNoveltyAndNoNaN) {
  const auto frames = Analyse(std::vector<float>(kRate / 10, 0.0f));
  ASSERT_FALSE(frames.empty());
  for (const auto& frame : frames) {
    EXPECT_EQ(frame.novelty_db, 0.0);
    EXPECT_FALSE(std::isnan(frame.noise_power));
  }
}

}  // namespace
}  // namespace bouncecal::audio
