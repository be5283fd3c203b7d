#include "sound_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

std::filesystem::path TempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("bouncecal_sound_file_" + name);
}

TEST(SoundFile, WrittenSamplesReadBackWithinPcm16Quantisation) {
  const auto path = TempPath("roundtrip.wav");
  const std::vector<float> written = {0.0f, 0.5f, -0.25f, 0.999f, -1.0f};
  {
    auto file = SoundFile::OpenForWriting(path, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16);
    file.WriteFrames(written);
  }
  auto file = SoundFile::OpenForReading(path);
  EXPECT_EQ(file.sample_rate_hz(), 48000);
  EXPECT_EQ(file.channels(), 1);
  std::vector<float> read(8);
  ASSERT_EQ(file.ReadFrames(read), 5);
  for (size_t i = 0; i < written.size(); ++i) {
    EXPECT_NEAR(read[i], written[i], 1.0 / 32768) << "sample " << i;  // one 16-bit LSB
  }
}

TEST(SoundFile, MissingFileNamesThePath) {
  try {
    SoundFile::OpenForReading("/nonexistent/ball.wav");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/ball.wav"), std::string::npos);
  }
}

TEST(SoundFile, TextFileRenamedWavIsRejected) {
  const auto path = TempPath("text.wav");
  std::ofstream(path) << "this is not audio\n";
  EXPECT_THROW(SoundFile::OpenForReading(path), InputError);
}

TEST(SoundFile, EmptyFileIsRejected) {
  const auto path = TempPath("empty.wav");
  std::ofstream(path).close();
  EXPECT_THROW(SoundFile::OpenForReading(path), InputError);
}

}  // namespace
}  // namespace bouncecal::audio
