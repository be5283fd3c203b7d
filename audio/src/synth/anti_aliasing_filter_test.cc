#include "synth/anti_aliasing_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

// |H(f)| of taps at f cycles per (high-rate) sample, by the direct sum (independent of the FFT
// the design measures itself with).
double Magnitude(const std::vector<double>& taps, double f) {
  const std::complex<double> step = std::polar(1.0, -2.0 * std::numbers::pi * f);
  std::complex<double> phasor = 1.0;
  std::complex<double> sum = 0.0;
  for (size_t k = 0; k < taps.size(); ++k) {
    // Re-anchored every 256 taps so the recursively turned phasor stays exact to ~1e-14.
    if (k % 256 == 0)
      phasor = std::polar(1.0, -2.0 * std::numbers::pi * f * static_cast<double>(k));
    sum += taps[k] * phasor;
    phasor *= step;
  }
  return std::abs(sum);
}

struct Measured {
  double passband_ripple_db = 0.0;
  double stopband_attenuation_db = 1000.0;
};

// The ripple over [0, passband edge] and the attenuation over [stopband edge, 0.5] (cycles per
// high-rate sample) on a grid of 8 points per 1/N, every local maximum of the stop band then
// refined by golden-section search, so the true lobe peaks are measured, not grid samples.
Measured Measure(const std::vector<double>& taps, int oversampling, double passband_fraction,
                 double stopband_fraction) {
  const double n = static_cast<double>(taps.size());
  const double step = 1.0 / (8.0 * n);
  Measured measured;
  for (double f = 0.0; f <= passband_fraction / oversampling; f += step / 4) {
    measured.passband_ripple_db =
        std::max(measured.passband_ripple_db, std::abs(20 * std::log10(Magnitude(taps, f))));
  }
  const double from = stopband_fraction / oversampling;
  std::vector<double> grid;
  for (double f = from; f <= 0.5; f += step) grid.push_back(Magnitude(taps, f));
  const auto golden_peak = [&](double lo, double hi) {
    constexpr double kInvPhi = 0.6180339887498949;
    double a = lo, b = hi;
    for (int i = 0; i < 40; ++i) {
      const double c = b - kInvPhi * (b - a), d = a + kInvPhi * (b - a);
      if (Magnitude(taps, c) > Magnitude(taps, d)) {
        b = d;
      } else {
        a = c;
      }
    }
    return Magnitude(taps, 0.5 * (a + b));
  };
  // With 8 points per 1/N a lobe peaks at most (pi / 16)^2 / 2 < 2 % above its largest grid
  // value, so only lobes within 5 % of the grid's largest can hold the true peak.
  const double grid_largest = *std::max_element(grid.begin(), grid.end());
  double worst = grid_largest;
  for (size_t i = 0; i < grid.size(); ++i) {
    const bool left = i == 0 || grid[i] >= grid[i - 1];
    const bool right = i + 1 == grid.size() || grid[i] >= grid[i + 1];
    if (!left || !right || grid[i] < 0.95 * grid_largest) continue;
    const double f = from + static_cast<double>(i) * step;
    worst = std::max(worst, golden_peak(std::max(from, f - step), std::min(0.5, f + step)));
  }
  measured.stopband_attenuation_db = -20 * std::log10(worst);
  return measured;
}

TEST(AntiAliasingFilter, DesignsMeetTheDataSheetSpecForBothPhasesAndSeveralOversamplings) {
  for (AdcFilterPhase phase : {AdcFilterPhase::kLinear, AdcFilterPhase::kMinimum}) {
    for (int oversampling : {2, 8, 24}) {
      const RecordingChain chain{.phase = phase, .oversampling = oversampling};
      const AntiAliasingFilter filter = DesignAntiAliasingFilter(chain, 48000);
      const Measured measured = Measure(filter.taps, oversampling, 0.4535, 0.5465);
      SCOPED_TRACE(std::string(ToString(phase)) + " x" + std::to_string(oversampling));
      // The spec: 100 dB from 0.5465 fs on (refined lobe peaks, so no grid allowance).
      EXPECT_GE(measured.stopband_attenuation_db, 100.0);
      // Kaiser's window leaves peak errors of about delta = 1e-5 in both bands (Kaiser 1974);
      // the unit-DC scaling and the cepstral conversion may each add up to delta: 3 delta is
      // 2.6e-4 dB, 20x tighter than the tightest data sheet (+-0.005 dB, AK4522).
      EXPECT_LE(measured.passband_ripple_db, 20 * std::log10(1 + 3e-5));
      // The design's own figures agree with this independent measurement.
      const FilterFigures own = MeasureFilter(filter.taps, oversampling, 0.4535, 0.5465);
      EXPECT_NEAR(own.stopband_attenuation_db, measured.stopband_attenuation_db, 0.05);
      EXPECT_NEAR(own.passband_ripple_db, measured.passband_ripple_db, 2e-5);
    }
  }
  // Another spec: a resampler's alias-free stop band from fs / 2, 120 dB.
  const RecordingChain resampler{
      .oversampling = 4, .stopband_edge_fraction = 0.5, .stopband_attenuation_db = 120.0};
  const Measured measured =
      Measure(DesignAntiAliasingFilter(resampler, 44100).taps, 4, 0.4535, 0.5);
  EXPECT_GE(measured.stopband_attenuation_db, 120.0);
  EXPECT_LE(measured.passband_ripple_db, 20 * std::log10(1 + 3e-6));
}

TEST(AntiAliasingFilter, LinearPhaseTapsAreSymmetricAndLeadByHalfTheirLength) {
  const AntiAliasingFilter filter = DesignAntiAliasingFilter(RecordingChain{}, 48000);
  const size_t n = filter.taps.size();
  ASSERT_EQ(n % 2, 1u);
  EXPECT_EQ(filter.oversampling, 8);  // automatic: 8 x 48 kHz reaches 384 kHz
  EXPECT_EQ(filter.lead, static_cast<int>(n - 1) / 2);
  const double largest = *std::max_element(filter.taps.begin(), filter.taps.end());
  for (size_t k = 0; k < n / 2; ++k) {
    // Each pair is computed from +-n, so only the last bit may differ.
    ASSERT_NEAR(filter.taps[k], filter.taps[n - 1 - k], 1e-15 * largest) << k;
  }
  // Band edges 0.4535 / 0.5465 put the cutoff at exactly fs / 2: every 8th tap from the centre
  // falls on a zero of the sinc (a Nyquist filter), so an impulse on an output sample does not
  // ring into the other output samples.
  const auto centre = static_cast<size_t>(filter.lead);
  for (size_t j = 8; j <= centre; j += 8) {
    EXPECT_NEAR(filter.taps[centre + j], 0.0, 1e-16) << j;
    EXPECT_NEAR(filter.taps[centre - j], 0.0, 1e-16) << j;
  }
  EXPECT_GT(std::abs(filter.taps[centre + 4]), 1e-3);
}

TEST(AntiAliasingFilter, MinimumPhaseHasTheSameMagnitudeAndTheLeastEnergyDelay) {
  const int taps = 555;
  const double cutoff = 0.5 / 8;
  const std::vector<double> linear = KaiserLowPass(taps, cutoff, KaiserBeta(100.5));
  const std::vector<double> minimum = MinimumPhase(linear, 1e-8);
  ASSERT_EQ(minimum.size(), linear.size());
  // Same magnitude: in the pass band to 3e-5 (the 3-delta allowance above, as a ratio), and in
  // the transition band, where the response falls through 60 dB, to 0.01 dB.
  for (double f = 0.0; f < 0.5465 / 8; f += 1.0 / (16.0 * taps)) {
    const double lin = Magnitude(linear, f);
    const double min = Magnitude(minimum, f);
    if (f <= 0.4535 / 8) {
      ASSERT_NEAR(min / lin, 1.0, 3e-5) << f;
    } else if (lin > 1e-3) {
      ASSERT_NEAR(20 * std::log10(min / lin), 0.0, 0.01) << f;
    }
  }
  // Of all filters with one magnitude response the minimum-phase one has the most energy in its
  // first m taps, for every m (Oppenheim & Schafer, "minimum energy delay"); the linear-phase one
  // holds its energy around the middle.
  double partial_linear = 0.0, partial_minimum = 0.0, total = 0.0;
  for (double h : linear) total += h * h;
  for (size_t m = 0; m < linear.size(); ++m) {
    partial_linear += linear[m] * linear[m];
    partial_minimum += minimum[m] * minimum[m];
    // The two energies agree to the magnitudes' 3e-5 (twice that as squares): no tighter.
    ASSERT_GE(partial_minimum, partial_linear - 6e-5 * total) << m;
  }
  EXPECT_NEAR(partial_minimum / total, 1.0, 6e-5);  // Parseval: same magnitude, same energy
  // And most of it early: half of the energy within the first 6 % of the taps, 4 output samples
  // (its main lobe peaks 26 taps in, as a sharp causal filter must lag; the linear-phase filter
  // needs 50 % of its taps).
  double early = 0.0;
  for (size_t m = 0; m < linear.size() * 6 / 100; ++m) early += minimum[m] * minimum[m];
  EXPECT_GT(early / total, 0.5);
}

TEST(AntiAliasingFilter, AutomaticOversamplingRendersAtLeast384KilohertzAndNeverBelow8) {
  EXPECT_EQ(ResolvedOversampling(RecordingChain{}, 16000), 24);
  EXPECT_EQ(ResolvedOversampling(RecordingChain{}, 44100), 9);
  EXPECT_EQ(ResolvedOversampling(RecordingChain{}, 96000), 8);
  EXPECT_EQ(ResolvedOversampling(RecordingChain{.oversampling = 3}, 16000), 3);
}

TEST(AntiAliasingFilter, ImpossibleChainsAreRefusedWithOneLine) {
  EXPECT_THROW(DesignAntiAliasingFilter(RecordingChain{.oversampling = 1}, 48000), ConfigError);
  EXPECT_THROW(DesignAntiAliasingFilter(RecordingChain{.stopband_edge_fraction = 0.4}, 48000),
               ConfigError);
  // 150 dB across a 0.001 fs transition at 64x needs ~6 million taps.
  EXPECT_THROW(DesignAntiAliasingFilter(RecordingChain{.oversampling = 64,
                                                       .passband_edge_fraction = 0.4995,
                                                       .stopband_edge_fraction = 0.5005,
                                                       .stopband_attenuation_db = 150.0},
                                        48000),
               ConfigError);
}

}  // namespace
}  // namespace bouncecal::audio
