#include "synth/modal_impact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

// Direct numerical convolution of the half-sine force with the mode's impulse response,
// composite Simpson on 20000 intervals: an independent check of the closed form.
double NumericalResponse(const PlateMode& mode, double tau, double t) {
  const double upper = std::min(t, tau);
  const int n = 20000;
  const double h = upper / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double u = i * h;
    const double force = std::numbers::pi / (2 * tau) * std::sin(std::numbers::pi * u / tau);
    const double impulse = mode.gain * std::exp(-(t - u) / mode.decay_s) *
                           std::sin(2 * std::numbers::pi * mode.frequency_hz * (t - u));
    const double weight = (i == 0 || i == n) ? 1 : (i % 2 == 1 ? 4 : 2);
    sum += weight * force * impulse;
  }
  return sum * h / 3;
}

TEST(ModalImpact, ClosedFormResponseMatchesNumericalConvolution) {
  const PlateMode mode{7300.0, 0.03, 0.8};
  const double tau = 70e-6;
  const ModeResponse response(mode, tau);
  // Inside the contact, at its end and long after; Simpson's error at this step is ~1e-12.
  for (double t : {10e-6, 35e-6, 70e-6, 71e-6, 0.4e-3, 5e-3}) {
    EXPECT_NEAR(response.Evaluate(t), NumericalResponse(mode, tau, t), 1e-9) << "t = " << t;
  }
  EXPECT_EQ(response.Evaluate(-1e-9), 0.0);
  EXPECT_EQ(response.Evaluate(0.0), 0.0);  // the force starts from zero: so does the response
}

TEST(ModalImpact, VeryShortContactTendsToTheImpulseResponse) {
  const PlateMode mode{2000.0, 0.05, 1.0};
  const ModeResponse response(mode, 1e-8);
  // The pulse's centroid sits tau/2 late, so the response lags the impulse response by ~5 ns:
  // a relative error of 2 pi f 5e-9 ~ 1e-4 on the slope; 1e-4 absolute covers it.
  for (double t : {1e-4, 1e-3, 7e-3}) {
    const double impulse = std::exp(-t / 0.05) * std::sin(2 * std::numbers::pi * 2000.0 * t);
    EXPECT_NEAR(response.Evaluate(t), impulse, 1e-4) << "t = " << t;
  }
}

TEST(ModalImpact, BankRendererEqualsSummingImpactsOneByOne) {
  // Two implementations of one thing: the recursive per-mode state versus each impact rendered
  // on its own, with overlapping tails, different contact durations and fractional onsets.
  const std::vector<PlateMode> modes = {
      {1100.0, 0.2, 1.0}, {5300.0, 0.05, -0.6}, {12100.0, 0.02, 0.4}};
  const std::vector<ModalExcitation> excitations = {
      {0.01003, 0.5, 70e-6}, {0.0731, 0.3, 80e-6}, {0.0732, 0.1, 20e-6}, {0.2, 0.05, 1e-3}};
  const double rate = 48000;
  std::vector<float> bank(20000, 0.0f);
  std::vector<float> single(20000, 0.0f);
  RenderModalExcitations(modes, excitations, rate, bank);
  for (const ModalExcitation& excitation : excitations) {
    ModalImpact(modes, excitation.contact_s)
        .Add(excitation.arrival_s, excitation.scale, rate, 0, single);
  }
  double worst = 0.0;
  for (size_t i = 0; i < bank.size(); ++i) {
    worst = std::max(worst, std::abs(double{bank[i]} - single[i]));
  }
  // Float accumulation of three modes and a few overlapping impacts: ~1e-7 of values ~0.5.
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(bank[481], 0.0f);  // before the first onset (481.44 samples)
  EXPECT_NE(bank[482], 0.0f);
}

}  // namespace
}  // namespace bouncecal::audio
