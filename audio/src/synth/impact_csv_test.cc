#include "bouncecal/audio/impact_csv.h"

#include <gtest/gtest.h>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

TEST(ImpactCsv, ReadsPlainPairsWithOrWithoutHeader) {
  const auto plain = ParseImpactCsv("0.5,1.98\n0.76, 1.2\r\n\n# comment\n0.93,0.8", "a.csv");
  ASSERT_EQ(plain.size(), 3u);
  EXPECT_DOUBLE_EQ(plain[1].onset_s, 0.76);
  EXPECT_DOUBLE_EQ(plain[1].impact_speed_mps, 1.2);
  const auto headed = ParseImpactCsv("onset_s,impact_speed_mps\n0.5,1.98\n", "b.csv");
  ASSERT_EQ(headed.size(), 1u);
}

TEST(ImpactCsv, TruthFilesFeedBackTheirBallImpactsOnly) {
  SynthesisOptions options;
  options.precursor = PrecursorOptions{};
  options.extra_events = {{SoundEventKind::kKnock, 0.05, 0.2}};
  options.drop.drop_count = 2;
  const SynthesizedRecording recording = SynthesizeBounces(options);
  const auto impacts = ParseImpactCsv(TruthCsv(recording), "truth.csv");
  const auto onsets = recording.BallImpactOnsetsS();
  ASSERT_EQ(impacts.size(), onsets.size());
  // TruthCsv writes 9 decimals: the round trip is exact to 0.5 ns.
  for (size_t i = 0; i < onsets.size(); ++i) EXPECT_NEAR(impacts[i].onset_s, onsets[i], 5e-10);
  EXPECT_EQ(impacts.front().drop_index, 0);
  EXPECT_EQ(impacts.back().drop_index, 1);
}

TEST(ImpactCsv, MalformedLinesNameTheSourceAndLine) {
  try {
    ParseImpactCsv("0.5,1.0\n0.7,fast\n", "bad.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.csv:2:"), std::string::npos) << error.what();
  }
  EXPECT_THROW(ParseImpactCsv("0.5\n", "one_column.csv"), InputError);
  EXPECT_THROW(ParseImpactCsv("0.5,-1\n", "negative.csv"), InputError);
  EXPECT_THROW(ParseImpactCsv("0.5,nan\n", "nan.csv"), InputError);
  EXPECT_THROW(ParseImpactCsv("onset_s,impact_speed_mps\n", "empty.csv"), InputError);
  EXPECT_THROW(ReadImpactCsv("/nonexistent/impacts.csv"), InputError);
}

}  // namespace
}  // namespace bouncecal::audio
