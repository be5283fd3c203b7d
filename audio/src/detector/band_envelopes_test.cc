#include "detector/band_envelopes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "detector/stage_test_support.h"
#include "detector/test_signals.h"

namespace bouncecal::audio {
namespace {

std::vector<float> Signal(int rate, double seconds) {
  std::vector<float> x(static_cast<std::size_t>(rate * seconds), 0.0f);
  testing::AddNoise(x, 1e-4, 7);
  testing::AddImpact(x, rate, 0.4, 0.5);
  return x;
}

// Every band's frames: the energies of the frames as they completed.
std::vector<std::vector<double>> Frames(std::span<const float> x, std::size_t piece) {
  testing::StageRig rig(48000);
  std::vector<std::vector<double>> frames(rig.bands.size());
  rig.Run(
      x,
      [&](std::int64_t n, std::ptrdiff_t) {
        for (std::size_t b = 0; b < rig.bands.size(); ++b) {
          frames[b].push_back(rig.bands.band(b).Power(n));
        }
      },
      piece);
  return frames;
}

// The filter works in its own blocks, so how the caller cuts the stream cannot change a frame.
TEST(BandEnvelopes, FramesDoNotDependOnHowTheStreamIsCut) {
  const auto x = Signal(48000, 1.0);
  const auto whole = Frames(x, 0);
  EXPECT_EQ(Frames(x, 997), whole);
  EXPECT_EQ(Frames(x, 4096), whole);
  ASSERT_EQ(whole.size(), 4u);  // band 0, the 2 and 6 kHz sub-bands and the low band at 48 kHz
  EXPECT_EQ(whole[0].size(), 4000u);  // 0.25 ms frames
}

// The rise windows' maxima, kept block by block over a frame buffer that the history moves to
// the front of only now and then, are exactly the maxima of the frames they span: over a stream
// of many filter blocks, every frame of every band, including the first frames (whose windows
// reach before the stream: nothing there counts).
TEST(BandEnvelopes, WindowMaximaAreTheMaximaOfTheirFrames) {
  const auto x = Signal(48000, 4.0);
  testing::StageRig rig(48000);
  const DetectorFrames& f = rig.frames;
  const std::int64_t lag = f.attack + f.skip;
  const std::int64_t reference = std::max<std::int64_t>(1, f.lookback - f.skip + 1);
  std::vector<std::vector<double>> powers(rig.bands.size());
  const auto max_of = [](const std::vector<double>& p, std::int64_t from, std::int64_t to) {
    double m = -std::numeric_limits<double>::infinity();
    for (std::int64_t i = std::max<std::int64_t>(from, 0); i <= to; ++i) {
      m = std::max(m, p[static_cast<std::size_t>(i)]);
    }
    return m;
  };
  std::int64_t checked = 0;
  rig.Run(x, [&](std::int64_t n, std::ptrdiff_t k) {
    for (std::size_t b = 0; b < rig.bands.size(); ++b) {
      const EnvelopeBand& band = rig.bands.band(b);
      powers[b].push_back(band.Power(n));
      ASSERT_EQ(band.AheadMax(k), max_of(powers[b], n - f.attack, n)) << "band " << b << " n " << n;
      ASSERT_EQ(band.ReferenceMax(k), max_of(powers[b], n - lag - (reference - 1), n - lag))
          << "band " << b << " n " << n;
      ++checked;
    }
  });
  EXPECT_EQ(checked, 4 * 16000);  // 4 s of 0.25 ms frames in 4 bands: ~45 filter blocks
}

// The rise compares the attack window with the lookback: an impact 0.5 full scale over noise of
// 1e-4 rms rises by about its peak power over the noise's loudest frame (20 log10(0.5 / 1e-4) =
// 74 dB less the crest of the impact's frames and the noise maximum, a few dB each); noise
// alone does not rise by half the threshold anywhere.
TEST(BandEnvelopes, AnImpactRisesByItsLevelOverTheNoiseAndNoiseDoesNotRise) {
  const auto x = Signal(48000, 1.0);
  testing::StageRig rig(48000);
  const std::int64_t onset_frame = static_cast<std::int64_t>(0.4 / rig.frames.frame_s);
  double rise_at_onset = -1e9;
  double rise_in_noise = -1e9;
  rig.Run(x, [&](std::int64_t n, std::ptrdiff_t k) {
    const std::int64_t m = n - rig.frames.attack;
    if (m < rig.frames.lookback) return;
    const double rise = rig.bands.Rise(0, k);
    if (m >= onset_frame - rig.frames.attack && m <= onset_frame) {
      rise_at_onset = std::max(rise_at_onset, rise);
    } else if (m < onset_frame - rig.frames.attack - 2) {
      rise_in_noise = std::max(rise_in_noise, rise);
      EXPECT_FALSE(rig.bands.AnyBandMayRise(k)) << n;
    }
  });
  EXPECT_GT(rise_at_onset, 55.0);
  EXPECT_LT(rise_at_onset, 80.0);
  EXPECT_LT(rise_in_noise, 5.0);
}

// A sub-band exists where its edge is above 1.5 times band 0's low edge and below 0.35 of the
// sample rate: both at 48 kHz, only the 2 kHz one at 16 kHz (6 kHz > 5.6 kHz). The low band
// (band 0 up to 2 kHz) follows the same rule for its upper edge, and comes last.
TEST(BandEnvelopes, SubBandsFollowTheSampleRate) {
  testing::StageRig at48(48000);
  ASSERT_EQ(at48.bands.size(), 4u);
  EXPECT_EQ(at48.bands.high_pass_bands(), 3u);
  EXPECT_EQ(at48.bands.low_hz(0), 300.0);
  EXPECT_EQ(at48.bands.low_hz(1), 2000.0);
  EXPECT_EQ(at48.bands.low_hz(2), 6000.0);
  EXPECT_TRUE(at48.bands.is_low_band(3));
  EXPECT_FALSE(at48.bands.is_low_band(0));
  testing::StageRig at16(16000);
  ASSERT_EQ(at16.bands.size(), 3u);
  EXPECT_EQ(at16.bands.high_pass_bands(), 2u);
  EXPECT_EQ(at16.bands.low_hz(1), 2000.0);
  EXPECT_TRUE(at16.bands.is_low_band(2));
}

// The low band passes a bounce's low modes and leaves out a hiss above a few kHz (what it is
// for, onset_locator.cc): 1 kHz within 1 dB, 8 kHz 35 dB or more under it (4th-order
// Butterworth at 2 kHz: 24 dB per octave over 2 octaves, 48 dB nominal, less the knee).
TEST(BandEnvelopes, TheLowBandPassesLowModesAndLeavesOutAHiss) {
  constexpr int kRate = 48000;
  const auto power_at = [&](double hz) {
    testing::StageRig rig(kRate);
    std::vector<float> tone(kRate);
    for (std::size_t i = 0; i < tone.size(); ++i) {
      tone[i] = static_cast<float>(0.1 * std::sin(2 * std::numbers::pi * hz * i / kRate));
    }
    double low = 0;
    double whole = 0;
    rig.Run(tone, [&](std::int64_t n, std::ptrdiff_t) {
      if (n > 2000) {  // past the filters' start
        low += rig.bands.band(3).Power(n);
        whole += rig.bands.band(0).Power(n);
      }
    });
    return 10 * std::log10(low / whole);
  };
  EXPECT_NEAR(power_at(1000.0), 0.0, 1.0);
  EXPECT_LT(power_at(8000.0), -35.0);
}

}  // namespace
}  // namespace bouncecal::audio
