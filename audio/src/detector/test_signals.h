#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_TEST_SIGNALS_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_TEST_SIGNALS_H_

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace bouncecal::audio::testing {

// A minimal impact for unit tests (the physically detailed synthesiser is audio::Synthesize-
// Bounces): three decaying sine modes starting together at exactly onset_s, so the pressure
// rises linearly from zero there, plus a short broadband click for the contact.
inline void AddImpact(std::vector<float>& x, int rate_hz, double onset_s, double amplitude,
                      double decay_s = 0.02) {
  const double modes_hz[3] = {2300.0, 4100.0, 6700.0};
  const double weights[3] = {1.0, 0.7, 0.5};
  const auto first = static_cast<long>(std::ceil(onset_s * rate_hz));
  const auto last =
      std::min<long>(static_cast<long>(x.size()), first + static_cast<long>(8 * decay_s * rate_hz));
  for (long i = std::max(first, 0L); i < last; ++i) {
    const double t = i / static_cast<double>(rate_hz) - onset_s;
    double value = 0;
    for (int m = 0; m < 3; ++m) {
      value += weights[m] * std::sin(2 * std::numbers::pi * modes_hz[m] * t);
    }
    // The contact itself: a broadband click of a few cycles, so an impact stands out even
    // when it excites the same modes as a louder ringing tail.
    const double click_hz = std::min(9000.0, 0.4 * rate_hz);
    const double click = 1.5 * std::exp(-t / 3e-4) * std::sin(2 * std::numbers::pi * click_hz * t);
    x[static_cast<size_t>(i)] +=
        static_cast<float>(amplitude / 2.2 * (std::exp(-t / decay_s) * value + click));
  }
}

inline void AddNoise(std::vector<float>& x, double rms, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> normal(0.0, rms);
  for (auto& v : x) v += static_cast<float>(normal(generator));
}

}  // namespace bouncecal::audio::testing

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_TEST_SIGNALS_H_
