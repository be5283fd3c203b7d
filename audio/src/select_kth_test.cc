#include "select_kth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// Exact selection: every rank of many random inputs (exponential like noise bin powers, with
// and without ties) must equal std::nth_element's answer bit for bit; no tolerance.
TEST(SelectKth, FindsTheSameValueAsNthElementForEveryRank) {
  std::mt19937 random(7);
  std::exponential_distribution<float> power(1.0f);
  std::uniform_int_distribution<int> level(0, 5);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(trial % 140);
    std::vector<float> values(n);
    for (auto& v : values) {
      // A third of the trials quantised to a few levels: many ties.
      v = trial % 3 == 0 ? static_cast<float>(level(random)) : power(random);
    }
    for (std::size_t k = 0; k < n; ++k) {
      auto expected = values;
      std::nth_element(expected.begin(), expected.begin() + static_cast<std::ptrdiff_t>(k),
                       expected.end());
      auto scratch = values;
      ASSERT_EQ(SelectKth(scratch, k), expected[k]) << "n " << n << " k " << k;
    }
  }
}

TEST(SelectKth, HandlesAllEqualAndSortedInputs) {
  std::vector<float> zeros(126, 0.0f);
  EXPECT_EQ(SelectKth(zeros, 31), 0.0f);
  std::vector<float> rising(126), falling(126);
  for (std::size_t i = 0; i < 126; ++i) {
    rising[i] = static_cast<float>(i);
    falling[i] = static_cast<float>(125 - i);
  }
  EXPECT_EQ(SelectKth(rising, 31), 31.0f);
  EXPECT_EQ(SelectKth(falling, 31), 31.0f);
}

}  // namespace
}  // namespace bouncecal::audio
