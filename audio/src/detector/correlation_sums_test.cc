#include "detector/correlation_sums.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace bouncecal::audio {
namespace {

std::vector<float> Signal(std::size_t size) {
  std::vector<float> x(size);
  for (std::size_t i = 0; i < size; ++i) {
    // Values of many magnitudes, so that the order of the additions would show in the sums.
    x[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i)) *
                              std::exp(-0.01 * static_cast<double>(i)) * (1 + (i % 7) * 1e3));
  }
  return x;
}

// Exact comparison with the loops the alignment ran per pair before the sums were kept: the same
// additions in the same order give the same doubles, and the results of the detector depend on it.
TEST(CorrelationSums, TemplateSumsEqualThePerLengthLoops) {
  const std::vector<float> x = Signal(300);
  for (std::size_t lead : {0u, 1u, 57u, 299u, 300u}) {
    const TemplateSums sums(x, lead);
    for (std::int64_t n = 0; n <= static_cast<std::int64_t>(x.size() - lead); ++n) {
      double energy = 0;
      double energy_squares = 0;
      double slope = 0;
      for (std::int64_t t = 0; t < n; ++t) {
        const double a = x[lead + static_cast<std::size_t>(t)];
        energy += a * a;
        energy_squares += a * a * a * a;
        if (t + 1 < n) {
          const double da = x[lead + static_cast<std::size_t>(t) + 1] - a;
          slope += da * da;
        }
      }
      ASSERT_EQ(sums.energy(n), energy) << "lead " << lead << " n " << n;
      ASSERT_EQ(sums.energy_squares(n), energy_squares) << "lead " << lead << " n " << n;
      ASSERT_EQ(sums.slope(n), slope) << "lead " << lead << " n " << n;
    }
  }
}

TEST(CorrelationSums, EnergyPrefixEqualsTheRunningSum) {
  for (std::size_t size : {0u, 1u, 2u, 301u}) {
    const std::vector<float> x = Signal(size);
    const std::vector<double> prefix = EnergyPrefix(x);
    ASSERT_EQ(prefix.size(), size + 1);
    double sum = 0;
    EXPECT_EQ(prefix[0], 0.0);
    for (std::size_t i = 0; i < size; ++i) {
      sum = sum + static_cast<double>(x[i]) * x[i];
      ASSERT_EQ(prefix[i + 1], sum) << "size " << size << " i " << i;
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio
