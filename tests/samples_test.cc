// The shipped samples must be what samples/make_samples.sh produces: rerun it and compare.
#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include "bouncecal/audio/impact_csv.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "io/sound_file.h"

namespace bouncecal::testing {
namespace {

std::vector<float> ReadAllFrames(const std::filesystem::path& path, int& channels, int& rate) {
  auto file = audio::SoundFile::OpenForReading(path);
  channels = file.channels();
  rate = file.sample_rate_hz();
  std::vector<float> samples;
  std::vector<float> block(4096 * static_cast<size_t>(channels));
  while (const auto frames = file.ReadFrames(block)) {
    samples.insert(samples.end(), block.begin(), block.begin() + frames * channels);
  }
  return samples;
}

TEST(Samples, ShippedSamplesMatchTheirDocumentedCommands) {
  const auto fresh = ScratchPath("samples");
  const std::string command = (SourceDir() / "samples" / "make_samples.sh").string() + " " +
                              BOUNCECAL_EXECUTABLE + " " + fresh.string() + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  for (const char* name : {"steel_ball_h0.2m", "pingpong_hard", "steel_ball_stereo_44k"}) {
    const auto shipped = SourceDir() / "samples" / (std::string(name) + ".wav");
    const auto regenerated = fresh / (std::string(name) + ".wav");
    ASSERT_LT(std::filesystem::file_size(shipped), 1000000u) << "samples must stay small";
    int shipped_channels = 0, shipped_rate = 0, channels = 0, rate = 0;
    const auto expected = ReadAllFrames(shipped, shipped_channels, shipped_rate);
    const auto actual = ReadAllFrames(regenerated, channels, rate);
    EXPECT_EQ(channels, shipped_channels) << name;
    EXPECT_EQ(rate, shipped_rate) << name;
    ASSERT_EQ(actual.size(), expected.size()) << name;
    double worst = 0.0;
    for (size_t i = 0; i < actual.size(); ++i) {
      worst = std::max(worst, std::abs(double{actual[i]} - expected[i]));
    }
    // Seeded and platform-independent random streams; only libm rounding may differ between
    // machines, which can flip a 16-bit sample by one step at a rounding boundary.
    EXPECT_LE(worst, 1.0 / 32768 + 1e-9) << name;

    const auto shipped_truth =
        audio::ReadImpactCsv(SourceDir() / "samples" / (std::string(name) + ".csv"));
    const auto truth = audio::ReadImpactCsv(fresh / (std::string(name) + ".csv"));
    ASSERT_EQ(truth.size(), shipped_truth.size()) << name;
    for (size_t i = 0; i < truth.size(); ++i) {
      EXPECT_NEAR(truth[i].onset_s, shipped_truth[i].onset_s, 1e-9) << name;  // 9 decimals
    }
  }
}

}  // namespace
}  // namespace bouncecal::testing
