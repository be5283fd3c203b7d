#include "plot/min_max_decimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal::apps {
namespace {

TEST(MinMaxDecimator, AMillionSamplesBecomeOneMinMaxPairPerColumnAndKeepAOneSampleClick) {
  const std::int64_t samples = 1'000'000;
  const int sample_rate_hz = 48000;
  MinMaxDecimator decimator(samples, 1000, sample_rate_hz);
  std::vector<float> block(4096);
  std::int64_t n = 0;
  const std::int64_t click = 654'321;
  while (n < samples) {
    block.resize(static_cast<std::size_t>(std::min<std::int64_t>(4096, samples - n)));
    for (auto& value : block) {
      value =
          n == click ? 0.9f : 0.01f * static_cast<float>(std::sin(0.1 * static_cast<double>(n)));
      ++n;
    }
    decimator.Add(block);
  }
  const auto columns = decimator.Finish();
  ASSERT_EQ(columns.time_s.size(), 1000u);
  // The click sits in column floor(click * 1000 / samples) = 654; only that column reaches it.
  EXPECT_FLOAT_EQ(static_cast<float>(columns.max[654]), 0.9f);
  EXPECT_LT(columns.max[653], 0.011);
  EXPECT_LT(columns.max[655], 0.011);
  // 1000 samples per column span 16 periods of the sine, so every column sees its extremes
  // to within the sample spacing: |sin| > 0.99 is reached (tolerance of 1 % of the amplitude).
  EXPECT_NEAR(columns.min[10], -0.01, 1e-4);
  // Column centres are the mean of the first and last sample time in the column.
  EXPECT_DOUBLE_EQ(columns.time_s[0], 0.5 * 999.0 / sample_rate_hz);
}

TEST(MinMaxDecimator, SamplesBeyondTheExpectedCountLandInTheLastColumn) {
  MinMaxDecimator decimator(10, 5, 10);
  std::vector<float> block(15, 0.0f);
  block[14] = -3.0f;
  decimator.Add(block);
  const auto columns = decimator.Finish();
  ASSERT_EQ(columns.min.size(), 5u);
  EXPECT_EQ(columns.min.back(), -3.0);
}

TEST(MinMaxDecimator, ShortSignalsLeaveEmptyColumnsOut) {
  MinMaxDecimator decimator(100, 50, 1000);
  const std::vector<float> block = {1.0f, 2.0f};
  decimator.Add(block);
  EXPECT_EQ(decimator.Finish().time_s.size(), 1u);
}

TEST(MinMaxDecimator, RejectsZeroColumnsWithAConfigError) {
  EXPECT_THROW(MinMaxDecimator(10, 0, 48000), ConfigError);
}

}  // namespace
}  // namespace bouncecal::apps
