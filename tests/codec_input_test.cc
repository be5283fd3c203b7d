// Phone formats and lossy codecs (issues 16 and 18): recordings encoded with Debian's `ffmpeg`
// command decode at their own rate with the encoder delay removed and report their codec. Every
// test skips with a message when ffmpeg is not installed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "bouncecal/audio/load_recording.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "lossy_encode.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

class CodecInput : public ::testing::Test {
 public:
  void SetUp() override {
    if (!FfmpegAvailable()) GTEST_SKIP() << FfmpegMissingMessage();
    folder_ = fs::temp_directory_path() /
              ("bouncecal_codec_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override {
    if (!folder_.empty()) fs::remove_all(folder_);
  }

  fs::path Encode(const fs::path& wav, const std::string& name,
                  const std::vector<std::string>& options) const {
    const fs::path out = folder_ / name;
    EXPECT_TRUE(EncodeWithFfmpeg(wav, out, options)) << name;
    return out;
  }

  fs::path folder_;
};

// A steel ball (e = 0.8, 12 impacts) on a plate whose modes ring for tens of ms, 30 dB SNR:
// broadband clicks whose cross-correlation peaks sharply at the true alignment.
audio::SynthesizedRecording Drop(std::uint64_t seed, int rate_hz = 48000, int channels = 1) {
  audio::SynthesisOptions options;
  options.seed = seed;
  options.drop.restitution.constant = 0.8;
  options.drop.min_flight_s = 0.03;
  options.sample_rate_hz = rate_hz;
  for (auto& mode : options.modes) mode.decay_s *= 0.1;
  audio::NoiseOptions noise;
  noise.snr_db = 30;
  options.noise = noise;
  options.channels.assign(static_cast<std::size_t>(channels), audio::ChannelOptions{});
  for (int c = 1; c < channels; ++c) {
    options.channels[static_cast<std::size_t>(c)].gain_db = -3.0 * c;
    options.channels[static_cast<std::size_t>(c)].delay_s = 2e-4 * c;
  }
  return audio::SynthesizeBounces(options);
}

fs::path WriteWav(const fs::path& path, const audio::SynthesizedRecording& recording,
                  audio::SampleEncoding encoding = audio::SampleEncoding::kPcm16) {
  audio::WriteRecording(path, recording.channels, {audio::AudioContainer::kWav, encoding});
  return path;
}

// The lag (samples) by which `decoded` trails `original`: the peak of their cross-correlation
// over +-4000 samples, on the 8192 samples from 10 ms before the first impact.
int LagSamples(const std::vector<float>& original, const std::vector<float>& decoded,
               std::size_t first_impact) {
  const std::size_t begin = first_impact - std::min<std::size_t>(first_impact, 480);
  const std::size_t end = std::min(original.size(), begin + 8192);
  double best = -1;
  int best_lag = 0;
  for (int lag = -4000; lag <= 4000; ++lag) {
    double sum = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const auto j = static_cast<std::ptrdiff_t>(i) + lag;
      if (j >= 0 && j < static_cast<std::ptrdiff_t>(decoded.size())) {
        sum += static_cast<double>(original[i]) * decoded[static_cast<std::size_t>(j)];
      }
    }
    if (sum > best) {
      best = sum;
      best_lag = lag;
    }
  }
  return best_lag;
}

TEST_F(CodecInput, LossyFilesDecodeAtTheirRateAlignedWithTheirWav) {
  const auto drop = Drop(3);
  const auto wav = WriteWav(folder_ / "drop.wav", drop);
  const auto& original = drop.channels[0].samples;
  const auto first =
      static_cast<std::size_t>(drop.BallImpactOnsetsS().front() * drop.channels[0].sample_rate_hz);
  struct Case {
    std::string name;
    std::vector<std::string> options;
    std::string decoder, container, codec;
    audio::EncoderDelay delay;
  };
  using audio::EncoderDelay;
  const std::vector<Case> cases = {
      // MP4 edit list (FFmpeg's AAC primes 1024 samples).
      {"aac.m4a", {"-c:a", "aac", "-b:a", "128k"}, "ffmpeg", "m4a", "aac", EncoderDelay::kRemoved},
      // LAME tag, read by libsndfile's mpg123 and by FFmpeg alike.
      {"lame.mp3",
       {"-c:a", "libmp3lame", "-b:a", "128k"},
       "libsndfile",
       "mp3",
       "mp3",
       EncoderDelay::kRemoved},
      // Opus pre-skip (312 samples) in Ogg and in WebM.
      {"opus.opus",
       {"-c:a", "libopus", "-b:a", "64k"},
       "libsndfile",
       "ogg",
       "opus",
       EncoderDelay::kRemoved},
      {"opus.webm",
       {"-c:a", "libopus", "-b:a", "64k"},
       "ffmpeg",
       "webm",
       "opus",
       EncoderDelay::kRemoved},
      // Vorbis in Ogg has no delay to remove: granule positions count from the first sample.
      {"vorbis.ogg",
       {"-c:a", "libvorbis", "-q:a", "5"},
       "libsndfile",
       "ogg",
       "vorbis",
       EncoderDelay::kNone},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto path = Encode(wav, c.name, c.options);
    const auto decoded = audio::LoadRecording(path);
    const audio::RecordingReader reader(path);
    const auto& info = reader.info();
    EXPECT_EQ(decoded.sample_rate_hz, 48000);
    EXPECT_EQ(info.decoder, c.decoder);
    EXPECT_EQ(info.container, c.container);
    EXPECT_EQ(info.codec, c.codec);
    EXPECT_TRUE(info.lossy);
    EXPECT_EQ(info.encoder_delay, c.delay);
    // Sample exact: a delay left in would be 312-1105 samples, one dropped twice as much.
    EXPECT_EQ(LagSamples(original, decoded.samples, first), 0);
  }
}

TEST_F(CodecInput, AnEncoderDelayTheFileDoesNotStateIsReportedUnknown) {
  const auto drop = Drop(4);
  const auto wav = WriteWav(folder_ / "drop.wav", drop);
  const auto first =
      static_cast<std::size_t>(drop.BallImpactOnsetsS().front() * drop.channels[0].sample_rate_hz);
  // ADTS has no field for it, an MP4 without an edit list and an MP3 without a LAME tag lose it.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"adts.aac", {"-c:a", "aac", "-b:a", "128k"}},
      {"no_edit_list.m4a", {"-c:a", "aac", "-b:a", "128k", "-use_editlist", "0"}},
      {"no_tag.mp3", {"-c:a", "libmp3lame", "-b:a", "128k", "-write_xing", "0"}},
  };
  for (const auto& [name, options] : cases) {
    SCOPED_TRACE(name);
    const auto path = Encode(wav, name, options);
    const audio::RecordingReader reader(path);
    EXPECT_EQ(reader.info().encoder_delay, audio::EncoderDelay::kUnknown);
    // Which is why it is reported: the onsets really are late, by the encoder's priming (1024
    // samples for FFmpeg's AAC, 1105 for LAME).
    EXPECT_GT(LagSamples(drop.channels[0].samples, audio::LoadRecording(path).samples, first),
              1000);
  }
}

TEST_F(CodecInput, LosslessCodecsThroughFfmpegGiveTheWavsSamplesExactly) {
  const auto drop = Drop(5, 44100, 2);
  const auto wav = WriteWav(folder_ / "drop24.wav", drop, audio::SampleEncoding::kPcm24);
  // ALAC in M4A (decoded as planar 32-bit) and FLAC in Matroska (libsndfile reads neither).
  for (const auto& [name, codec] : std::vector<std::pair<std::string, std::string>>{
           {"alac.m4a", "alac"}, {"flac.mka", "flac"}}) {
    SCOPED_TRACE(name);
    const auto path = Encode(wav, name, {"-c:a", codec});
    const audio::RecordingReader reader(path);
    EXPECT_EQ(reader.info().decoder, "ffmpeg");
    EXPECT_EQ(reader.info().codec, codec);
    EXPECT_FALSE(reader.info().lossy);
    EXPECT_EQ(reader.info().encoder_delay, audio::EncoderDelay::kNone);
    EXPECT_EQ(reader.info().sample_rate_hz, 44100);
    for (int channel = 0; channel < 2; ++channel) {
      // Bit for bit: 24-bit integers are exact in float both ways, and the channel order holds.
      EXPECT_EQ(audio::LoadRecording(path, channel).samples,
                audio::LoadRecording(wav, channel).samples)
          << "channel " << channel;
    }
  }
}

}  // namespace
}  // namespace bouncecal::testing
