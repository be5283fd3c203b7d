#include "bouncecal/audio/load_recording.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"
#include "io/sound_file.h"

namespace bouncecal::audio {
namespace {

using bouncecal::testing::ScratchPath;

std::filesystem::path TempPath(const std::string& name) { return ScratchPath(name); }

void Write(const std::filesystem::path& path, int rate, int channels, int format,
           const std::vector<float>& interleaved) {
  auto file = SoundFile::OpenForWriting(path, rate, channels, format);
  file.WriteFrames(interleaved);
}

std::string ErrorOf(const std::filesystem::path& path) {
  try {
    LoadRecording(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(LoadRecording, PicksTheRequestedChannelOfAStereo24BitFile) {
  const auto path = TempPath("stereo24.wav");
  std::vector<float> interleaved;
  for (int i = 0; i < 1000; ++i) {
    interleaved.push_back(0.5f * std::sin(0.01f * i));
    interleaved.push_back(-0.25f);
  }
  Write(path, 96000, 2, SF_FORMAT_WAV | SF_FORMAT_PCM_24, interleaved);
  const auto right = LoadRecording(path, 1);
  EXPECT_EQ(right.sample_rate_hz, 96000);
  EXPECT_EQ(right.source_channel_count, 2);
  ASSERT_EQ(right.samples.size(), 1000u);
  // One 24-bit LSB.
  EXPECT_NEAR(right.samples[500], -0.25f, 1.0 / (1 << 23));
  const auto left = LoadRecording(path, 0);
  EXPECT_NEAR(left.samples[300], 0.5f * std::sin(3.0f), 1.0 / (1 << 23));
  EXPECT_THROW(LoadRecording(path, 2), ConfigError);
}

TEST(LoadRecording, FloatFileKeepsItsValues) {
  const auto path = TempPath("float.wav");
  Write(path, 16000, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT, {0.1f, -0.7f, 0.3f});
  const auto recording = LoadRecording(path);
  ASSERT_EQ(recording.samples.size(), 3u);
  EXPECT_EQ(recording.samples[1], -0.7f);  // float is stored exactly
}

TEST(LoadRecording, NanSampleIsAOneLineErrorNamingTheFile) {
  const auto path = TempPath("nan.wav");
  Write(path, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT,
        {0.1f, std::numeric_limits<float>::quiet_NaN(), 0.2f});
  const auto message = ErrorOf(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("NaN"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(LoadRecording, ZeroOrOneSampleIsRejected) {
  const auto none = TempPath("zero.wav");
  Write(none, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16, {});
  EXPECT_NE(ErrorOf(none).find("0 sample"), std::string::npos) << ErrorOf(none);
  const auto one = TempPath("one.wav");
  Write(one, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16, {0.5f});
  EXPECT_NE(ErrorOf(one).find("1 sample"), std::string::npos) << ErrorOf(one);
}

TEST(LoadRecording, TruncatedWavIsRejected) {
  const auto whole = TempPath("whole.wav");
  Write(whole, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16, std::vector<float>(48000, 0.1f));
  const auto cut = TempPath("cut.wav");
  std::ifstream in(whole, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_NE(ErrorOf(cut).find("truncated"), std::string::npos) << ErrorOf(cut);
}

TEST(LoadRecording, TextFileAndMissingFileAreInputErrors) {
  const auto text = TempPath("text.wav");
  std::ofstream(text) << "hello\n";
  EXPECT_NE(ErrorOf(text).find(text.string()), std::string::npos);
  EXPECT_NE(ErrorOf("/nonexistent/x.wav").find("/nonexistent/x.wav"), std::string::npos);
}

TEST(LoadRecording, RateBelow8kHzIsRejected) {
  const auto path = TempPath("slow.wav");
  Write(path, 4000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16, std::vector<float>(100, 0.0f));
  EXPECT_NE(ErrorOf(path).find("8000"), std::string::npos) << ErrorOf(path);
}

}  // namespace
}  // namespace bouncecal::audio
