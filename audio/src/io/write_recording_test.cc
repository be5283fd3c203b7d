#include "bouncecal/audio/write_recording.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"
#include "io/sound_file.h"

namespace bouncecal::audio {
namespace {

using bouncecal::testing::ScratchSubfolder;

size_t FileCount(const std::filesystem::path& dir) {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator(dir),
                                           std::filesystem::directory_iterator()));
}

// Two different channels (a decaying 1 kHz tone and its negated, halved copy) at 44.1 kHz.
std::vector<Recording> StereoTone() {
  std::vector<Recording> channels(2);
  for (int c = 0; c < 2; ++c) {
    channels[c].sample_rate_hz = 44100;
    channels[c].samples.resize(5000);
    for (size_t i = 0; i < 5000; ++i) {
      const double tone = 0.9 * std::exp(-static_cast<double>(i) / 2000.0) *
                          std::sin(2 * 3.14159265358979 * 1000.0 * static_cast<double>(i) / 44100);
      channels[c].samples[i] = static_cast<float>(c == 0 ? tone : -0.5 * tone);
    }
  }
  return channels;
}

struct Case {
  AudioContainer container;
  SampleEncoding encoding;
  double tolerance;  // the encoding's quantisation step (round to nearest: half a step suffices)
};

TEST(WriteRecording, WrittenChannelsReadBackWithRateChannelsAndSamplesWithinQuantisation) {
  const auto dir = ScratchSubfolder("roundtrip");
  const std::vector<Recording> channels = StereoTone();
  const Case cases[] = {
      {AudioContainer::kWav, SampleEncoding::kPcm16, 1.0 / 32768},
      {AudioContainer::kWav, SampleEncoding::kPcm24, 1.0 / 8388608},
      // 32-bit PCM is finer than the float samples themselves: float rounding (6e-8 at 0.9).
      {AudioContainer::kWav, SampleEncoding::kPcm32, 1e-7},
      {AudioContainer::kWav, SampleEncoding::kFloat, 0.0},
      {AudioContainer::kFlac, SampleEncoding::kPcm16, 1.0 / 32768},
      {AudioContainer::kFlac, SampleEncoding::kPcm24, 1.0 / 8388608},
  };
  for (const Case& test : cases) {
    const auto path = dir / (std::string("tone_") + std::string(ToString(test.encoding)) + "." +
                             std::string(ToString(test.container)));
    const auto summary = WriteRecording(path, channels, {test.container, test.encoding});
    EXPECT_EQ(summary.frames, 5000);
    EXPECT_EQ(summary.clipped_samples, 0);
    SoundFile file = SoundFile::OpenForReading(path);
    EXPECT_EQ(file.sample_rate_hz(), 44100) << path;
    ASSERT_EQ(file.channels(), 2) << path;
    std::vector<float> interleaved(2 * 6000);
    ASSERT_EQ(file.ReadFrames(interleaved), 5000) << path;
    double worst = 0.0;
    for (size_t i = 0; i < 5000; ++i) {
      for (size_t c = 0; c < 2; ++c) {
        worst = std::max(worst, std::abs(double{interleaved[2 * i + c]} - channels[c].samples[i]));
      }
    }
    EXPECT_LE(worst, test.tolerance) << path;
  }
}

TEST(WriteRecording, SamplesBeyondFullScaleAreCountedAsClippedForIntegerEncodings) {
  const auto dir = ScratchSubfolder("clip");
  Recording loud;
  loud.sample_rate_hz = 48000;
  loud.samples = {0.5f, 1.5f, -2.0f, 0.1f};
  EXPECT_EQ(WriteRecording(dir / "a.wav", std::span(&loud, 1)).clipped_samples, 2);
  EXPECT_EQ(WriteRecording(dir / "b.wav", std::span(&loud, 1), {.encoding = SampleEncoding::kFloat})
                .clipped_samples,
            0);
  SoundFile file = SoundFile::OpenForReading(dir / "a.wav");
  std::vector<float> read(4);
  ASSERT_EQ(file.ReadFrames(read), 4);
  EXPECT_NEAR(read[1], 1.0, 1.0 / 32768);  // clipped to full scale, not wrapped around
  EXPECT_NEAR(read[2], -1.0, 1.0 / 32768);
}

TEST(WriteRecording, FailuresLeaveNoFileBehindAndKeepAnExistingOne) {
  const auto dir = ScratchSubfolder("fail");
  std::vector<Recording> channels = StereoTone();
  WriteRecording(dir / "keep.wav", channels);
  const auto size_before = std::filesystem::file_size(dir / "keep.wav");
  channels[1].samples.pop_back();  // unequal lengths
  EXPECT_THROW(WriteRecording(dir / "keep.wav", channels), ConfigError);
  EXPECT_THROW(
      WriteRecording(dir / "x.flac", StereoTone(), {AudioContainer::kFlac, SampleEncoding::kFloat}),
      ConfigError);
  EXPECT_THROW(WriteRecording(dir / "missing" / "x.wav", StereoTone()), OutputError);
  EXPECT_THROW(WriteRecording(dir / "x.wav", std::span<const Recording>()), ConfigError);
  EXPECT_EQ(std::filesystem::file_size(dir / "keep.wav"), size_before);
  EXPECT_EQ(FileCount(dir), 1u);  // no temporaries, no partial outputs
}

TEST(WriteRecording, EncodingNamesRoundTripAndUnknownNamesAreConfigErrors) {
  for (auto encoding : {SampleEncoding::kPcm16, SampleEncoding::kPcm24, SampleEncoding::kPcm32,
                        SampleEncoding::kFloat}) {
    EXPECT_EQ(SampleEncodingFromString(ToString(encoding)), encoding);
  }
  EXPECT_THROW(SampleEncodingFromString("mp3"), ConfigError);
  EXPECT_EQ(ContainerForPath("a/b.FLAC"), AudioContainer::kFlac);
  EXPECT_EQ(ContainerForPath("a/b.wav"), AudioContainer::kWav);
}

// libsndfile would add a PEAK chunk holding the wall-clock time of writing to float WAVs, which
// makes the same recording differ in bytes between runs (issue 7: byte-identical outputs).
TEST(WriteRecording, FloatWavCarriesNoTimestampedPeakChunk) {
  const auto dir = ScratchSubfolder("peak_chunk");
  const auto path = dir / "float.wav";
  WriteRecordingOptions options;
  options.encoding = SampleEncoding::kFloat;
  WriteRecording(path, StereoTone(), options);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.find("PEAK"), std::string::npos);
}

}  // namespace
}  // namespace bouncecal::audio
