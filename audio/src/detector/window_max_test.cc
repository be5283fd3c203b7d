#include "detector/window_max.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// Against the maximum taken directly over each run of `window` values, for window lengths
// around and at powers of two, the detector's (9 and 47 frames at 48 kHz) and the whole input,
// on values with ties and runs and on minus infinity (the rise windows' padding before the
// first frame); exact, as a maximum is not computed.
TEST(WindowMaxima, EqualsTheDirectMaximumOfEveryWindow) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> level(0, 20);
  std::vector<double> stream(500);
  for (auto& x : stream) x = level(random) * 0.5;
  std::fill_n(stream.begin(), 60, -std::numeric_limits<double>::infinity());
  std::vector<double> scratch;
  for (std::size_t window : {1u, 2u, 3u, 4u, 5u, 8u, 9u, 16u, 17u, 32u, 33u, 41u, 47u, 64u, 500u}) {
    for (std::size_t size : {window, window + 1, window + 7, std::size_t{500}}) {
      if (size > stream.size()) continue;
      const std::span<const double> x(stream.data() + stream.size() - size, size);
      std::vector<double> maxima(size - window + 1);
      WindowMaxima(x, window, maxima, scratch);
      for (std::size_t i = 0; i < maxima.size(); ++i) {
        const double expected =
            *std::max_element(x.begin() + static_cast<std::ptrdiff_t>(i),
                              x.begin() + static_cast<std::ptrdiff_t>(i + window));
        ASSERT_EQ(maxima[i], expected) << "window " << window << " size " << size << " at " << i;
      }
    }
    // Only as many as maxima holds.
    std::vector<double> fewer(3, -1.0);
    WindowMaxima(stream, window, std::span<double>(fewer).first(2), scratch);
    EXPECT_EQ(fewer[2], -1.0);
  }
}

// The all minus infinity windows before the first frame stay minus infinity.
TEST(WindowMaxima, KeepsMinusInfinityWhereThereIsNothingElse) {
  const double minus_infinity = -std::numeric_limits<double>::infinity();
  std::vector<double> x(60, minus_infinity);
  x.push_back(2.0);
  std::vector<double> maxima(x.size() - 46), scratch;
  WindowMaxima(x, 47, maxima, scratch);
  for (std::size_t i = 0; i + 1 < maxima.size(); ++i) ASSERT_EQ(maxima[i], minus_infinity);
  EXPECT_EQ(maxima.back(), 2.0);
}

}  // namespace
}  // namespace bouncecal::audio
