#include "bouncecal/audio/codec_timing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace bouncecal::audio {
namespace {

// bench/codec_timing_bench (docs/codecs.md), 16 seeds of two scenes: per family, the sigma of
// the onset shifts against the WAV's (95 % within 1.96 sigma) at the encoder settings whose
// measured bit rate falls in each class, the largest over 16, 44.1 and 48 kHz. The class
// boundary sits between the settings measured: FFmpeg's AAC at 64 and 128 kbit/s (61-65 and 130
// kbit/s as decoded; 128k at 16 kHz is capped to 63), LAME at 64 and 128/192 kbit/s, libvorbis q2
// and q5 (74-75 and 99-100 kbit/s; 36 and 47 at 16 kHz), libopus 24 and 64 kbit/s (32-33 and
// 72-78). G.711 (mu-law, A-law) and ADPCM (IMA, Microsoft) code sample by sample, without a
// transform block: one class each (the threshold 0 puts every known bit rate in it). Rows
// measured with the detector of this commit: a detector change calls for a re-run
// (tests/codec_input_test.cc checks the high bit rate rows on other drops).
struct FamilyTiming {
  std::string_view family;
  double high_bit_rate_bps_per_channel;
  double low_s;
  double high_s;
};

constexpr std::array<FamilyTiming, 6> kMeasured = {{
    {"aac", 96000, 1408e-6, 967e-6},
    {"mp3", 96000, 722e-6, 96e-6},
    {"vorbis", 90000, 568e-6, 327e-6},
    {"opus", 48000, 1410e-6, 248e-6},
    {"g711", 0, 41e-6, 41e-6},
    {"adpcm", 0, 220e-6, 220e-6},
}};

// The frame each transform codec draws its quantisation noise for (CodecTiming::frame_s), in
// samples of the decoded rate, long blocks: AAC-LC 1024; MP3 a granule of 576 (two per MPEG-1
// frame, one per MPEG-2 frame); Vorbis the hop of libvorbis's long block, 2048 / 2; Opus the
// encoders' 20 ms (libopus's default; its own lengths run 2.5-60 ms). A codec whose frame is not
// known here (AMR, WMA, AC-3, ...) takes the longest of these at its rate: the onsets any of
// them could have moved are widened.
struct FamilyFrame {
  std::string_view family;
  double samples;  // 0: a fixed duration, `seconds`
  double seconds;
};

constexpr std::array<FamilyFrame, 4> kFrames = {{
    {"aac", 1024, 0},
    {"mp3", 576, 0},
    {"vorbis", 1024, 0},
    {"opus", 0, 20e-3},
}};

double FrameSeconds(const FamilyFrame& frame, int sample_rate_hz) {
  return frame.samples > 0 ? frame.samples / sample_rate_hz : frame.seconds;
}

std::optional<double> FrameOf(std::string_view family, int sample_rate_hz) {
  if (family == "g711" || family == "adpcm" || sample_rate_hz <= 0) return std::nullopt;
  double longest = 0;
  for (const auto& frame : kFrames) {
    if (frame.family == family) return FrameSeconds(frame, sample_rate_hz);
    longest = std::max(longest, FrameSeconds(frame, sample_rate_hz));
  }
  return longest;
}

std::string_view FamilyOf(const std::string& codec) {
  if (codec == "aac" || codec == "aac_latm") return "aac";
  if (codec == "mp3") return "mp3";
  if (codec == "vorbis") return "vorbis";
  if (codec == "opus") return "opus";
  // libsndfile's and FFmpeg's names for the same codings.
  if (codec == "pcm_mulaw" || codec == "pcm_alaw") return "g711";
  if (codec == "adpcm_ima" || codec == "adpcm_ima_wav" || codec == "adpcm_ms") return "adpcm";
  return "other";
}

}  // namespace

std::optional<CodecTiming> CodecTimingOf(const RecordingInfo& info) {
  if (!info.lossy) return std::nullopt;
  CodecTiming timing;
  timing.family = FamilyOf(info.codec);
  timing.frame_s = FrameOf(timing.family, info.sample_rate_hz);
  const auto found = std::find_if(kMeasured.begin(), kMeasured.end(),
                                  [&](const auto& row) { return row.family == timing.family; });
  if (found == kMeasured.end()) {
    timing.measured = false;
    for (const auto& row : kMeasured) {
      timing.onset_uncertainty_s = std::max({timing.onset_uncertainty_s, row.low_s, row.high_s});
    }
    return timing;
  }
  timing.high_bit_rate_bps_per_channel = found->high_bit_rate_bps_per_channel;
  timing.high_bit_rate =
      info.bit_rate_bps && info.channel_count > 0 &&
      *info.bit_rate_bps / info.channel_count >= found->high_bit_rate_bps_per_channel;
  timing.onset_uncertainty_s = timing.high_bit_rate ? found->high_s : found->low_s;
  return timing;
}

void WidenOnsetUncertainties(DetectionResult& detection, double sigma_s) {
  for (auto* impacts : {&detection.impacts, &detection.tentative}) {
    for (auto& impact : *impacts) {
      impact.onset_uncertainty_s = std::hypot(impact.onset_uncertainty_s, sigma_s);
    }
  }
}

}  // namespace bouncecal::audio
