#include "synth/recording_chain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "synth/contact_click.h"

namespace bouncecal::audio {
namespace {

// A deterministic, broadband test signal (no randomness needed: a sum of incommensurate tones
// with a ramp reaches every phase of every tap).
std::vector<float> TestSignal(size_t size) {
  std::vector<float> x(size);
  for (size_t i = 0; i < size; ++i) {
    const double t = static_cast<double>(i);
    x[i] = static_cast<float>(0.5 * std::sin(0.0131 * t) + 0.3 * std::sin(1.7 * t + 0.2) +
                              0.2 * std::sin(2.9 * t * (1.0 + 1e-4 * t)));
  }
  return x;
}

TEST(Decimate, EqualsFilteringAtTheHighRateThenKeepingEveryMthSample) {
  for (AdcFilterPhase phase : {AdcFilterPhase::kLinear, AdcFilterPhase::kMinimum}) {
    const AntiAliasingFilter filter =
        DesignAntiAliasingFilter(RecordingChain{.phase = phase, .oversampling = 4}, 48000);
    const int m = filter.oversampling;
    const auto taps = static_cast<std::int64_t>(filter.taps.size());
    // The input covers high-rate indices [-300, 2700); outside it the signal is zero.
    const std::int64_t input_first = -300;
    const std::vector<float> input = TestSignal(3000);
    const auto x = [&](std::int64_t j) {
      const std::int64_t i = j - input_first;
      return i >= 0 && i < std::ssize(input) ? double{input[static_cast<size_t>(i)]} : 0.0;
    };
    // Outputs -200..699: some read only zeros, some straddle either end of the input.
    const std::int64_t first_output = -200;
    std::vector<float> out(900);
    Decimate(filter, input, input_first, first_output, out);
    double worst = 0.0;
    for (size_t i = 0; i < out.size(); ++i) {
      // The high-rate convolution z[j] = sum_k h[k] x[j - k], read at j = n M + lead.
      const std::int64_t j = (first_output + static_cast<std::int64_t>(i)) * m + filter.lead;
      double z = 0.0;
      for (std::int64_t k = 0; k < taps; ++k) z += filter.taps[static_cast<size_t>(k)] * x(j - k);
      worst = std::max(worst, std::abs(z - double{out[i]}));
    }
    // Float output of values below ~1: rounding 6e-8; summation order differs.
    EXPECT_LT(worst, 2e-7) << ToString(phase);
    EXPECT_EQ(out.front(), 0.0f);  // reads only the zeros before the input
  }
}

TEST(Decimate, ReadsExactlyTheHighRateRangeItsOutputsNeed) {
  const AntiAliasingFilter filter = DesignAntiAliasingFilter(RecordingChain{}, 48000);
  const HighRateRange range = DecimatorInput(filter, 10, 5);
  const auto taps = static_cast<std::int64_t>(filter.taps.size());
  EXPECT_EQ(range.first, 10 * 8 + filter.lead - (taps - 1));
  EXPECT_EQ(range.first + range.count - 1, 14 * 8 + filter.lead);
  // A signal that is non-zero only outside that range leaves those outputs exactly zero.
  std::vector<float> input(static_cast<size_t>(range.count + 2), 0.0f);
  input.front() = 1.0f;
  input.back() = 1.0f;
  std::vector<float> out(5);
  Decimate(filter, input, range.first - 1, 10, out);
  for (float y : out) EXPECT_EQ(y, 0.0f);
}

// Renders one click (peak 1) through the filter: its contact starts at onset_samples (output
// samples, fractional) and lasts contact_s.
std::vector<float> ClickThroughChain(const AntiAliasingFilter& filter, double rate_hz,
                                     double onset_samples, double contact_s, size_t outputs) {
  const double high_rate_hz = rate_hz * filter.oversampling;
  const HighRateRange range = DecimatorInput(filter, 0, static_cast<std::int64_t>(outputs));
  std::vector<float> high(static_cast<size_t>(range.count), 0.0f);
  const ContactClick click{onset_samples / rate_hz, 1.0, contact_s};
  AddContactClicks(std::span(&click, 1), high_rate_hz, range.first, high);
  std::vector<float> out(outputs);
  Decimate(filter, high, range.first, 0, out);
  return out;
}

TEST(RecordingChain, LinearPhaseGivesASymmetricResponseToAClickCentredBetweenOrOnSamples) {
  constexpr double kRate = 48000;
  constexpr double kContactS = 35e-6;
  const AntiAliasingFilter filter = DesignAntiAliasingFilter(RecordingChain{}, kRate);
  ASSERT_EQ(filter.oversampling, 8);
  // Centre (the force's peak) at 200.5 and at 200 output samples: with M = 8 both lie on the
  // high-rate grid, so the sampled half-sine is itself symmetric about the centre.
  const double contact_samples = kContactS * kRate;
  const auto between =
      ClickThroughChain(filter, kRate, 200.5 - contact_samples / 2, kContactS, 400);
  const auto on = ClickThroughChain(filter, kRate, 200.0 - contact_samples / 2, kContactS, 400);
  const double peak = *std::max_element(between.begin(), between.end());
  ASSERT_GT(peak, 0.5);
  double asymmetry_between = 0.0, asymmetry_on = 0.0, before = 0.0;
  for (size_t j = 0; j < 150; ++j) {
    asymmetry_between =
        std::max(asymmetry_between, std::abs(double{between[200 - j]} - between[201 + j]));
    asymmetry_on = std::max(asymmetry_on, std::abs(double{on[200 - j]} - on[200 + j]));
    if (j >= 1) before = std::max(before, std::abs(double{between[200 - j]}));
  }
  // Rounding of the sample times against the onset and float storage: ~1e-7 of the peak. A
  // group delay compensated by one high-rate sample too many or too few (1/8 sample) breaks
  // the symmetry by ~10 % of the peak.
  EXPECT_LT(asymmetry_between, 1e-6 * peak);
  EXPECT_LT(asymmetry_on, 1e-6 * peak);
  // And the click rings well before its contact: the zero-phase artefact itself.
  EXPECT_GT(before, 0.05 * peak);
}

double BesselI0(double x) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 200; ++k) {
    term *= (x * x / 4) / (static_cast<double>(k) * k);
    sum += term;
  }
  return sum;
}

TEST(RecordingChain, LinearPhasePreRingingBeforeTheOnsetIsWhatTheDesignPredicts) {
  // The design's continuous impulse response h_c(s) = 2 fc sinc(2 fc s) w(s / T) / g (Kaiser
  // window w of half-length T = lead / R, g the scaling to unit DC gain) convolved with the
  // contact force gives every output sample, before and after the onset:
  //   y(t_n) = int_0^tau sin(pi u / tau) h_c(t_n - u) du.
  // 64x oversampling (3.07 MHz) makes the chain's sampling of the click exact to ~2e-5 (a
  // Riemann sum of a function with kinks at the contact's ends, error ~ pi / (12 (R tau)^2)).
  constexpr double kRate = 48000;
  constexpr double kContactS = 35e-6;
  const AntiAliasingFilter filter =
      DesignAntiAliasingFilter(RecordingChain{.oversampling = 64}, kRate);
  const double high_rate = kRate * 64;
  const double onset_samples = 150.3;  // between samples: the case that pre-rings most
  const auto y = ClickThroughChain(filter, kRate, onset_samples, kContactS, 300);

  const double fc = filter.cutoff_cycles_per_sample * high_rate;  // Hz
  const double half_s = filter.lead / high_rate;
  double g = 0.0;
  const auto unscaled = [&](double s) {
    if (std::abs(s) > half_s) return 0.0;
    const double x = 2 * fc * s;
    const double sinc = x == 0.0 ? 1.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
    const double r = s / half_s;
    return 2 * fc * sinc * BesselI0(filter.kaiser_beta * std::sqrt(1 - r * r)) /
           BesselI0(filter.kaiser_beta);
  };
  for (int k = -filter.lead; k <= filter.lead; ++k) g += unscaled(k / high_rate) / high_rate;
  const auto predicted = [&](double t_s) {  // Simpson over the contact, 2000 intervals
    constexpr int kIntervals = 2000;
    const double h = kContactS / kIntervals;
    double sum = 0.0;
    for (int i = 0; i <= kIntervals; ++i) {
      const double u = i * h;
      const double weight = i == 0 || i == kIntervals ? 1 : (i % 2 == 1 ? 4 : 2);
      sum += weight * std::sin(std::numbers::pi * u / kContactS) * unscaled(t_s - u);
    }
    return sum * h / 3 / g;
  };
  const double onset_s = onset_samples / kRate;
  double energy_before = 0.0, predicted_before = 0.0, worst = 0.0;
  for (size_t n = 0; n < y.size(); ++n) {
    const double t_s = static_cast<double>(n) / kRate;
    const double expected = predicted(t_s - onset_s);
    worst = std::max(worst, std::abs(double{y[n]} - expected));
    if (t_s < onset_s) {
      energy_before += double{y[n]} * y[n];
      predicted_before += expected * expected;
    }
  }
  const double peak = *std::max_element(y.begin(), y.end());
  // Sampling error ~2e-5 of the peak plus float storage: 1e-4 of the peak for any sample, 1 %
  // for the energy before the onset (samples of 1-10 % of the peak there).
  EXPECT_LT(worst, 1e-4 * peak);
  EXPECT_NEAR(energy_before / predicted_before, 1.0, 0.01);
  EXPECT_GT(energy_before, 1e-3 * peak * peak);  // and there is such energy to predict
}

TEST(RecordingChain, MinimumPhaseLeavesEverySampleBeforeTheOnsetExactlyZero) {
  constexpr double kRate = 16000;
  const AntiAliasingFilter filter =
      DesignAntiAliasingFilter(RecordingChain{.phase = AdcFilterPhase::kMinimum}, kRate);
  EXPECT_EQ(filter.lead, 0);
  for (double onset_samples : {100.0, 100.25, 100.999}) {
    const auto y = ClickThroughChain(filter, kRate, onset_samples, 70e-6, 300);
    for (size_t n = 0; n <= 100; ++n) {
      if (static_cast<double>(n) < onset_samples) {
        ASSERT_EQ(y[n], 0.0f) << n;
      }
    }
    // The click has not vanished: it comes out after the onset, delayed and smeared.
    EXPECT_GT(*std::max_element(y.begin(), y.end()), 0.1);
  }
}

}  // namespace
}  // namespace bouncecal::audio
