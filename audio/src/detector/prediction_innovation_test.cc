#include "detector/prediction_innovation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace bouncecal::audio {
namespace {

std::vector<float> TwoModes(std::size_t n) {
  std::vector<float> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / 48000.0;
    x[i] = static_cast<float>(0.4 * std::exp(-t / 0.2) * std::sin(2 * std::numbers::pi * 1250 * t) +
                              0.2 * std::exp(-t / 0.1) *
                                  std::sin(2 * std::numbers::pi * 5890 * t + 1));
  }
  return x;
}

TEST(PredictionInnovation, RemovesRingingAndKeepsANewImpulse) {
  auto x = TwoModes(400);
  const std::size_t impulse = 300;
  x[impulse] += 0.01f;  // 30 dB below the ringing's amplitude
  const std::size_t fit_end = 250;
  const int order = 24;
  const auto e = PredictionInnovation(x, fit_end, order);
  ASSERT_EQ(e.size(), x.size() - order);
  // Two damped modes are an order-4 autoregression, so the predictor removes them: over the
  // fit region the innovation is at least 30 dB below the signal (the autocorrelation method's
  // edge effects and float samples leave ~40 dB). The first innovation sample after the fit
  // region that stands 3 sigma above that is the impulse, at its own index (a[0] = 1 passes
  // it through; the following samples carry a[j] times it, which may be larger).
  double signal_power = 0;
  double innovation_power = 0;
  for (std::size_t i = order; i < fit_end; ++i) {
    signal_power += double{x[i]} * x[i];
    innovation_power += double{e[i - order]} * e[i - order];
  }
  EXPECT_LT(innovation_power, 1e-3 * signal_power);
  const double sigma = std::sqrt(innovation_power / static_cast<double>(fit_end - order));
  std::size_t first = e.size();
  for (std::size_t i = fit_end - order; i < e.size() && first == e.size(); ++i) {
    if (std::fabs(e[i]) > 3.0 * sigma) first = i;
  }
  EXPECT_EQ(first + order, impulse);
}

TEST(PredictionInnovation, TooFewSamplesToFitReturnTheSignal) {
  const auto x = TwoModes(100);
  const auto e = PredictionInnovation(x, 50, 24);  // fewer than 4 * 24 samples to fit on
  ASSERT_EQ(e.size(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(e[i], x[i]);
}

}  // namespace
}  // namespace bouncecal::audio
