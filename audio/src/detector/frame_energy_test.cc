#include "detector/frame_energy.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// Four frames at a time and the frames left over give each frame's SumOfSquares divided by the
// hop, to the bit: for hops that are and are not multiples of four (the samples after the last
// four of a frame), the detector's (12 samples: 0.25 ms at 48 kHz) among them, and for counts
// around multiples of four.
TEST(FrameMeanSquares, EqualsEachFramesSumOfSquaresOverTheHop) {
  std::mt19937 random(5);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  std::vector<float> x(17 * 11);
  for (auto& v : x) v = noise(random);
  for (std::size_t hop = 1; hop <= 17; ++hop) {
    for (std::size_t count = 0; count <= 11; ++count) {
      std::vector<double> out(count + 1, -1.0);
      FrameMeanSquares(x.data(), hop, count, out.data());
      for (std::size_t k = 0; k < count; ++k) {
        const double expected = SumOfSquares({x.data() + k * hop, hop}) / static_cast<double>(hop);
        ASSERT_EQ(out[k], expected) << "hop " << hop << " count " << count << " frame " << k;
      }
      EXPECT_EQ(out[count], -1.0) << "hop " << hop << " count " << count;
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio
