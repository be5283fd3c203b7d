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

// Several windows at once, each from its own offset, equal each window alone over its part of
// the values: shorter and longer windows sharing some or all passes (the detector's 9 and 47
// frames among them), equal windows, a window of one, and as many maxima as each holds.
TEST(WindowMaxima, SeveralWindowsAtOnceEqualEachAlone) {
  std::mt19937 random(11);
  std::uniform_int_distribution<int> level(0, 30);
  std::vector<double> x(420);
  for (auto& v : x) v = level(random) * 0.25;
  std::fill_n(x.begin(), 20, -std::numeric_limits<double>::infinity());
  std::vector<double> scratch, alone_scratch;
  const std::vector<std::vector<std::size_t>> window_sets = {{9, 47},     {1, 47},   {2, 3}, {4, 4},
                                                             {5, 17, 33}, {47, 100}, {1, 1}};
  for (const auto& windows : window_sets) {
    std::vector<std::vector<double>> maxima;
    std::vector<WindowRun> runs;
    const std::size_t longest = windows.back();
    for (std::size_t w = 0; w < windows.size(); ++w) {
      const std::size_t offset = longest - windows[w] + w;  // ends aligned, then shifted
      maxima.emplace_back(x.size() - offset - windows[w] + 1 - w, -1.0);  // w fewer than fit
    }
    for (std::size_t w = 0; w < windows.size(); ++w) {
      runs.push_back({longest - windows[w] + w, windows[w], maxima[w]});
    }
    WindowMaxima(x, runs, scratch);
    for (std::size_t w = 0; w < windows.size(); ++w) {
      std::vector<double> alone(maxima[w].size());
      WindowMaxima(std::span<const double>(x).subspan(runs[w].offset), windows[w], alone,
                   alone_scratch);
      EXPECT_EQ(maxima[w], alone) << "window " << windows[w] << " of set " << windows.front();
      for (std::size_t i = 0; i < alone.size(); ++i) {
        const auto begin = x.begin() + static_cast<std::ptrdiff_t>(runs[w].offset + i);
        ASSERT_EQ(alone[i],
                  *std::max_element(begin, begin + static_cast<std::ptrdiff_t>(windows[w])))
            << "window " << windows[w] << " at " << i;
      }
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio
