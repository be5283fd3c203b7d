#include "detector/window_max.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// Against the maximum taken directly over the last `window` values (fewer at the start), for
// several window lengths and a stream with ties and runs; exact, as a maximum is not computed.
TEST(WindowMax, EqualsTheDirectMaximumOfTheLastValues) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> level(0, 20);
  std::vector<double> stream(500);
  for (auto& x : stream) x = level(random) * 0.5;
  for (std::size_t window : {1u, 2u, 3u, 8u, 41u, 600u}) {
    WindowMax sliding(window);
    for (std::size_t i = 0; i < stream.size(); ++i) {
      sliding.Push(stream[i]);
      const std::size_t first = i + 1 >= window ? i + 1 - window : 0;
      const double expected =
          *std::max_element(stream.begin() + static_cast<std::ptrdiff_t>(first),
                            stream.begin() + static_cast<std::ptrdiff_t>(i + 1));
      ASSERT_EQ(sliding.max(), expected) << "window " << window << " value " << i;
    }
  }
}

// PushBlock gives after every value exactly what Push and max() give, whatever the block sizes
// (blocks shorter and longer than the window, across its block boundaries).
TEST(WindowMax, PushBlockGivesWhatSinglePushesGive) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  std::vector<double> stream(700);
  for (auto& x : stream) x = value(random);
  for (std::size_t window : {1u, 3u, 8u, 41u}) {
    WindowMax singles(window), blocks(window);
    std::size_t at = 0;
    for (std::size_t size : {0u, 5u, 1u, 100u, 7u, 41u, 300u, 246u}) {
      std::vector<double> maxima(size);
      blocks.PushBlock(std::span<const double>(stream).subspan(at, size), maxima.data());
      for (std::size_t i = 0; i < size; ++i) {
        singles.Push(stream[at + i]);
        ASSERT_EQ(maxima[i], singles.max()) << "window " << window << " value " << at + i;
      }
      ASSERT_EQ(blocks.max(), singles.max());
      at += size;
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio
