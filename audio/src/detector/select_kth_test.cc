#include "detector/select_kth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace bouncecal::audio {
namespace {

// 1-140 values (by trial) like a spectrum's noise bin powers: exponential, or, in a third of the
// trials, quantised to a few levels (many ties).
std::vector<float> BinPowers(std::mt19937& random, int trial) {
  std::exponential_distribution<float> power(1.0f);
  std::uniform_int_distribution<int> level(0, 5);
  std::vector<float> values(1 + static_cast<std::size_t>(trial % 140));
  for (auto& v : values) v = trial % 3 == 0 ? static_cast<float>(level(random)) : power(random);
  return values;
}

// Exact selection: every rank of many random inputs (exponential like noise bin powers, with
// and without ties) must equal std::nth_element's answer bit for bit; no tolerance. One
// scratch buffer serves inputs of every size, and the input itself is left as it was.
TEST(SelectKth, FindsTheSameValueAsNthElementForEveryRank) {
  std::mt19937 random(7);
  std::vector<float> scratch;
  for (int trial = 0; trial < 300; ++trial) {
    const std::vector<float> values = BinPowers(random, trial);
    const std::size_t n = values.size();
    for (std::size_t k = 0; k < n; ++k) {
      auto expected = values;
      std::nth_element(expected.begin(), expected.begin() + static_cast<std::ptrdiff_t>(k),
                       expected.end());
      const auto before = values;
      ASSERT_EQ(SelectKth(values, k, scratch), expected[k]) << "n " << n << " k " << k;
      ASSERT_EQ(values, before);
    }
  }
}

// The guess only saves time: a guess at the answer itself, near it (so the answer's rank falls
// inside or just outside the bracket the guess spans), far from it, or none of use (zero,
// negative, infinite, NaN) gives std::nth_element's value bit for bit; no tolerance.
TEST(SelectKth, FindsTheSameValueWhateverTheGuess) {
  std::mt19937 random(11);
  std::vector<float> scratch;
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<float> values = BinPowers(random, trial);
    const std::size_t n = values.size();
    for (std::size_t k = 0; k < n; ++k) {
      auto sorted = values;
      std::sort(sorted.begin(), sorted.end());
      const float answer = sorted[k];
      for (const float guess :
           {answer, 0.7f * answer, 1.5f * answer, 0.3f * answer, 3.0f * answer, sorted.front(),
            sorted.back(), 1e-30f, 1e30f, 0.0f, -1.0f, std::numeric_limits<float>::infinity(),
            std::numeric_limits<float>::quiet_NaN()}) {
        ASSERT_EQ(SelectKth(values, k, scratch, guess), answer)
            << "n " << n << " k " << k << " guess " << guess;
      }
    }
  }
}

// Infinite values (a float bin power can overflow) and guesses whose upper bracket edges
// overflow to infinity: the bracket above the highest edge has no upper bound, so infinite
// values are still found at their ranks.
TEST(SelectKth, FindsInfiniteValuesAndSurvivesOverflowingEdges) {
  std::mt19937 random(13);
  std::exponential_distribution<float> power(1.0f);
  std::vector<float> scratch;
  const float infinity = std::numeric_limits<float>::infinity();
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<float> values(1 + static_cast<std::size_t>(trial));
    for (std::size_t i = 0; i < values.size(); ++i) {
      values[i] = i % 5 == 0 ? infinity : 3e38f * power(random);
    }
    auto sorted = values;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < values.size(); ++k) {
      for (const float guess : {sorted[k], std::numeric_limits<float>::max(), 1.0f}) {
        ASSERT_EQ(SelectKth(values, k, scratch, guess), sorted[k])
            << "n " << values.size() << " k " << k << " guess " << guess;
      }
    }
  }
}

TEST(SelectKth, HandlesAllEqualAndSortedInputs) {
  std::vector<float> scratch;
  std::vector<float> zeros(126, 0.0f);
  EXPECT_EQ(SelectKth(zeros, 31, scratch), 0.0f);
  std::vector<float> rising(126), falling(126);
  for (std::size_t i = 0; i < 126; ++i) {
    rising[i] = static_cast<float>(i);
    falling[i] = static_cast<float>(125 - i);
  }
  EXPECT_EQ(SelectKth(rising, 31, scratch), 31.0f);
  EXPECT_EQ(SelectKth(falling, 31, scratch), 31.0f);
}

}  // namespace
}  // namespace bouncecal::audio
