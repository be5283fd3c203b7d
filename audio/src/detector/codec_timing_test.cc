#include "bouncecal/audio/codec_timing.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bouncecal::audio {
namespace {

RecordingInfo Lossy(const std::string& codec, std::optional<double> bit_rate_bps,
                    int channels = 1) {
  RecordingInfo info;
  info.codec = codec;
  info.lossy = true;
  info.channel_count = channels;
  info.bit_rate_bps = bit_rate_bps;
  return info;
}

TEST(CodecTiming, LosslessInputAddsNothing) {
  RecordingInfo wav;
  wav.codec = "pcm_s16";
  wav.channel_count = 1;
  EXPECT_FALSE(CodecTimingOf(wav).has_value());
}

TEST(CodecTiming, TheBitRatePerChannelPicksTheClass) {
  const auto high = CodecTimingOf(Lossy("mp3", 128000));
  const auto low = CodecTimingOf(Lossy("mp3", 64000));
  ASSERT_TRUE(high && low);
  EXPECT_EQ(high->family, "mp3");
  EXPECT_TRUE(high->high_bit_rate);
  EXPECT_FALSE(low->high_bit_rate);
  // A lower bit rate never promises better timing.
  EXPECT_GT(low->onset_uncertainty_s, high->onset_uncertainty_s);
  // 128 kbit/s over two channels is 64 per channel: the low class.
  EXPECT_EQ(CodecTimingOf(Lossy("mp3", 128000, 2))->onset_uncertainty_s, low->onset_uncertainty_s);
}

TEST(CodecTiming, AnUnknownBitRateTakesTheLargerError) {
  const auto unknown = CodecTimingOf(Lossy("aac", std::nullopt));
  const auto low = CodecTimingOf(Lossy("aac", 32000));
  ASSERT_TRUE(unknown && low);
  EXPECT_FALSE(unknown->high_bit_rate);
  EXPECT_EQ(unknown->onset_uncertainty_s, low->onset_uncertainty_s);
}

TEST(CodecTiming, ACodecTheBenchDidNotMeasureGetsTheLargestMeasuredError) {
  const auto amr = CodecTimingOf(Lossy("amr_nb", 12200));
  ASSERT_TRUE(amr);
  EXPECT_FALSE(amr->measured);
  EXPECT_EQ(amr->family, "other");
  for (const std::string codec : {"aac", "mp3", "vorbis", "opus"}) {
    for (double rate : {16000.0, 320000.0}) {
      EXPECT_GE(amr->onset_uncertainty_s, CodecTimingOf(Lossy(codec, rate))->onset_uncertainty_s)
          << codec << " " << rate;
    }
  }
}

// Telephony's sample-by-sample codecs were measured (docs/codecs.md): a phone system's mu-law
// WAV is no longer given the largest transform codec's error, 36 times its own.
TEST(CodecTiming, SampleBySampleCodecsHaveTheirOwnMeasuredError) {
  for (const std::string codec :
       {"pcm_mulaw", "pcm_alaw", "adpcm_ima", "adpcm_ima_wav", "adpcm_ms"}) {
    const auto timing = CodecTimingOf(Lossy(codec, std::nullopt));
    ASSERT_TRUE(timing) << codec;
    EXPECT_TRUE(timing->measured) << codec;
    EXPECT_EQ(timing->family, codec.starts_with("pcm_") ? "g711" : "adpcm");
    // One class: the bit rate, known or not, does not change it.
    EXPECT_EQ(timing->onset_uncertainty_s, CodecTimingOf(Lossy(codec, 64000))->onset_uncertainty_s);
    EXPECT_LT(timing->onset_uncertainty_s,
              CodecTimingOf(Lossy("amr_nb", 12200))->onset_uncertainty_s / 5);
  }
}

TEST(CodecTiming, WideningAddsInQuadratureToImpactsAndTentativeOnes) {
  DetectionResult detection;
  detection.impacts.resize(2);
  detection.impacts[0].onset_uncertainty_s = 30e-6;
  detection.impacts[1].onset_uncertainty_s = 0;
  detection.tentative.resize(1);
  detection.tentative[0].onset_uncertainty_s = 400e-6;
  WidenOnsetUncertainties(detection, 40e-6);
  EXPECT_NEAR(detection.impacts[0].onset_uncertainty_s, 50e-6, 1e-15);  // 3-4-5
  EXPECT_NEAR(detection.impacts[1].onset_uncertainty_s, 40e-6, 1e-15);
  EXPECT_NEAR(detection.tentative[0].onset_uncertainty_s, std::hypot(400e-6, 40e-6), 1e-15);
}

}  // namespace
}  // namespace bouncecal::audio
