#include "io/sound_file.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <fstream>
#include <vector>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::audio {
namespace {

using bouncecal::testing::ScratchPath;

std::filesystem::path TempPath(const std::string& name) { return ScratchPath(name); }

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

// 16-bit PCM is read as integers and scaled here: every one of the 65536 codes, in a stereo
// file read in blocks that do not divide it, must give exactly the float libsndfile's own
// conversion gives (sf_readf_float with normalisation), bit for bit; no tolerance.
TEST(SoundFile, Pcm16ReadsAsTheSameFloatsAsLibsndfilesConversion) {
  const auto path = TempPath("all_codes.wav");
  std::vector<short> codes(65536);
  for (std::size_t i = 0; i < codes.size(); ++i) {
    codes[i] = static_cast<short>(static_cast<int>(i) - 32768);
  }
  {
    SF_INFO info{};
    info.samplerate = 48000;
    info.channels = 2;
    info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
    SNDFILE* raw = sf_open(path.c_str(), SFM_WRITE, &info);
    ASSERT_NE(raw, nullptr);
    ASSERT_EQ(sf_writef_short(raw, codes.data(), 32768), 32768);
    sf_close(raw);
  }
  std::vector<float> expected(codes.size());
  {
    SF_INFO info{};
    SNDFILE* raw = sf_open(path.c_str(), SFM_READ, &info);
    ASSERT_NE(raw, nullptr);
    sf_command(raw, SFC_SET_NORM_FLOAT, nullptr, SF_TRUE);
    ASSERT_EQ(sf_readf_float(raw, expected.data(), 32768), 32768);
    sf_close(raw);
  }
  auto file = SoundFile::OpenForReading(path);
  std::vector<float> read;
  std::vector<float> block(2 * 1000);
  while (const auto frames = file.ReadFrames(block)) {
    read.insert(read.end(), block.begin(), block.begin() + 2 * frames);
  }
  ASSERT_EQ(read.size(), expected.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(read[i]), std::bit_cast<std::uint32_t>(expected[i]))
        << "code " << codes[i];
  }
  EXPECT_EQ(read.front(), -1.0f);
  EXPECT_EQ(read.back(), 32767.0f / 32768.0f);
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
