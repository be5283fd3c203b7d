#include "io/ffmpeg_decoder.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bouncecal/audio/load_recording.h"
#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"
#include "io/ffmpeg_library.h"
#include "io/sound_file.h"

namespace bouncecal::audio {
namespace {

using bouncecal::testing::ScratchFolder;

namespace fs = std::filesystem;

class FfmpegDecoderTest : public ::testing::Test {
 public:
  fs::path WriteText(const std::string& name, const std::string& text) const {
    std::ofstream(folder_ / name, std::ios::binary) << text;
    return folder_ / name;
  }

  // A stereo 16-bit WAV of `frames` frames: a decaying tone left, a ramp right.
  fs::path WriteStereoWav(const std::string& name, int frames) const {
    std::vector<float> interleaved;
    for (int i = 0; i < frames; ++i) {
      interleaved.push_back(0.5f * std::exp(-i / 3000.0f) * std::sin(0.07f * i));
      interleaved.push_back(static_cast<float>(i % 200) / 400.0f - 0.25f);
    }
    auto file =
        SoundFile::OpenForWriting(folder_ / name, 44100, 2, SF_FORMAT_WAV | SF_FORMAT_PCM_16);
    file.WriteFrames(interleaved);
    return folder_ / name;
  }

  const ScratchFolder folder_;
};

TEST_F(FfmpegDecoderTest, AWavDecodesToLibsndfilesSamplesWhateverTheBlockSize) {
  const auto wav = WriteStereoWav("tone.wav", 10007);
  std::string why_not;
  const auto decoder = FfmpegDecoder::Open(wav, &why_not);
  ASSERT_NE(decoder, nullptr) << why_not;
  EXPECT_EQ(decoder->sample_rate_hz(), 44100);
  EXPECT_EQ(decoder->channels(), 2);
  EXPECT_EQ(decoder->container(), "wav");
  EXPECT_EQ(decoder->codec(), "pcm_s16le");
  EXPECT_FALSE(decoder->lossy());
  EXPECT_EQ(decoder->encoder_delay(), EncoderDelay::kNone);
  // Blocks of 7 frames cut across every decoded frame boundary.
  std::vector<float> decoded, block(14);
  while (const auto got = decoder->ReadFrames(block)) {
    decoded.insert(decoded.end(), block.begin(), block.begin() + 2 * got);
  }
  auto reference = SoundFile::OpenForReading(wav);
  std::vector<float> expected(2 * 10007 + 2);
  expected.resize(2 * static_cast<std::size_t>(reference.ReadFrames(expected)));
  // Bit for bit: both scale 16-bit integers by 1/32768.
  EXPECT_EQ(decoded, expected);
}

// Whether this process has any of FFmpeg's libraries mapped.
bool FfmpegIsMapped() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    if (line.find("libavformat") != std::string::npos ||
        line.find("libavcodec") != std::string::npos) {
      return true;
    }
  }
  return false;
}

// FFmpeg is loaded by the first file that needs it, not by the program: a WAV or FLAC analysis
// never maps its ~130 libraries (56 ms of every process start when they were linked). Each half
// runs in a fresh process (a death-test child), since an earlier test may have loaded it here.
TEST_F(FfmpegDecoderTest, FfmpegIsLoadedByTheFirstFileThatNeedsItAndOnlyThen) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto wav = WriteStereoWav("tone.wav", 4000);
  EXPECT_EXIT(
      {
        const bool before = FfmpegIsMapped();
        LoadRecording(wav);
        std::exit(!before && !FfmpegIsMapped() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        std::string why_not;
        const bool opened = FfmpegDecoder::Open(wav, &why_not) != nullptr;
        std::exit(opened && FfmpegIsMapped() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
  std::string why_not;
  const FfmpegLibrary* first = LoadFfmpeg(&why_not);
  ASSERT_NE(first, nullptr) << why_not;
  EXPECT_EQ(LoadFfmpeg(nullptr), first);
}

TEST_F(FfmpegDecoderTest, PlaylistsAndScriptsThatWouldOpenOtherFilesAreNotFollowed) {
  WriteStereoWav("secret.wav", 4410);
  const auto playlist = WriteText("list.m3u8",
                                  "#EXTM3U\n#EXT-X-TARGETDURATION:1\n#EXTINF:0.1,\nsecret.wav\n"
                                  "#EXT-X-ENDLIST\n");
  const auto concat = WriteText("list.ffconcat", "ffconcat version 1.0\nfile 'secret.wav'\n");
  for (const auto& path : {playlist, concat}) {
    std::string why_not;
    EXPECT_EQ(FfmpegDecoder::Open(path, &why_not), nullptr) << path;
    EXPECT_FALSE(why_not.empty());
  }
}

TEST_F(FfmpegDecoderTest, RandomBytesAndTextAreNotMedia) {
  std::mt19937 random(7);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(random());
  for (const auto& path : {WriteText("noise.m4a", noise), WriteText("notes.m4a", "drop 1\n")}) {
    std::string why_not;
    EXPECT_EQ(FfmpegDecoder::Open(path, &why_not), nullptr) << path;
    EXPECT_FALSE(why_not.empty());
  }
}

TEST_F(FfmpegDecoderTest, AnMp4HeaderOverGarbageIsRefusedInOneLine) {
  std::mt19937 random(11);
  std::string bytes(
      "\0\0\0\x18"
      "ftypM4A \0\0\0\0M4A mp42",
      24);
  for (int i = 0; i < 2000; ++i) bytes.push_back(static_cast<char>(random()));
  const auto path = WriteText("garbage.m4a", bytes);
  try {
    std::string why_not;
    EXPECT_EQ(FfmpegDecoder::Open(path, &why_not), nullptr);
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos);
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace bouncecal::audio
