// Phone formats and lossy codecs (issues 16 and 18): recordings encoded with Debian's `ffmpeg`
// command decode at their own rate with the encoder delay removed, report their codec, and carry
// the codec's measured timing error in every onset uncertainty the response timing did not
// state (issue 30), in `bouncecal analyze` and in the calibration input alike. Every test skips
// with a message when ffmpeg is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/codec_timing.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/load_recording.h"
#include "bouncecal/audio/response_timing.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/calibrate/recording_analysis.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "lossy_encode.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

class CodecInput : public ::testing::Test {
 public:
  void SetUp() override {
    if (!FfmpegAvailable()) GTEST_SKIP() << FfmpegMissingMessage();
  }

  fs::path Encode(const fs::path& wav, const std::string& name,
                  const std::vector<std::string>& options) const {
    const fs::path out = folder_ / name;
    EXPECT_TRUE(EncodeWithFfmpeg(wav, out, options)) << name;
    return out;
  }

  const ScratchFolder folder_;
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

// The one recording of an analyze --json document (bouncecal-analysis/1, docs/json.md).
nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  const auto document = nlohmann::json::parse(in);
  EXPECT_EQ(document["format"], "bouncecal-analysis/1");
  EXPECT_EQ(document["recordings"].size(), 1u);
  return document["recordings"][0];
}

// How far a lossy copy's eta-bar lies from its WAV's (the first sequence of each, as `bouncecal
// analyze --json` reports it): the difference and the two stated sigmas combined.
struct EtaBarAgreement {
  double difference = 0;
  double stated = 0;
};

// The first sequence `bouncecal analyze` reports for `file` (its JSON written into `folder`).
nlohmann::json FirstSequence(const fs::path& file, const fs::path& folder) {
  const auto json = folder / (file.filename().string() + ".json");
  const auto run = RunBouncecal("analyze '" + file.string() + "' --json '" + json.string() + "'");
  EXPECT_EQ(run.exit_status, 0) << file;
  return ReadJson(json)["sequences"][0];
}

EtaBarAgreement CompareSequences(const nlohmann::json& reference, const nlohmann::json& lossy) {
  return {std::fabs(lossy["energy_loss_mean_first_n"].get<double>() -
                    reference["energy_loss_mean_first_n"].get<double>()),
          std::hypot(reference["energy_loss_mean_first_n_uncertainty"].get<double>(),
                     lossy["energy_loss_mean_first_n_uncertainty"].get<double>())};
}

// A copy may refuse (no sequence or no eta-bar); where it answers, its eta-bar must lie within
// `sigmas` combined sigmas of the WAV's.
void ExpectTheWavsEtaBarOrNone(const nlohmann::json& reference, const nlohmann::json& lossy,
                               double sigmas) {
  if (lossy.is_null() || !lossy["energy_loss_mean_first_n"].is_number()) return;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, sigmas * combined) << difference << " vs " << combined;
}

// The copy's first sequence is the WAV's drop: it starts within `onset_s` of the WAV's first
// onset, and its eta-bar lies within `line` and within 3 combined sigmas of the WAV's.
void ExpectTheWavsDrop(const nlohmann::json& reference, const nlohmann::json& copy, double onset_s,
                       double line) {
  ASSERT_FALSE(copy.is_null());
  ASSERT_TRUE(copy["energy_loss_mean_first_n"].is_number());
  EXPECT_NEAR(copy["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), onset_s);
  const auto [difference, combined] = CompareSequences(reference, copy);
  EXPECT_LE(difference, line) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// The copy's first sequence has an eta-bar, within `line` of the WAV's.
void ExpectTheWavsEtaBar(const nlohmann::json& reference, const nlohmann::json& copy, double line) {
  ASSERT_FALSE(copy.is_null());
  ASSERT_TRUE(copy["energy_loss_mean_first_n"].is_number());
  const auto [difference, combined] = CompareSequences(reference, copy);
  EXPECT_LE(difference, line) << difference << " vs " << combined;
}

EtaBarAgreement CompareCopyWithItsWav(const fs::path& wav, const fs::path& copy,
                                      const fs::path& folder) {
  return CompareSequences(FirstSequence(wav, folder), FirstSequence(copy, folder));
}

// Onset k of the copy's first sequence less the WAV's, and the copy's stated sigma of it.
struct OnsetAgreement {
  double error = 0;
  double stated = 0;
};

OnsetAgreement CompareOnsets(const nlohmann::json& reference, const nlohmann::json& lossy,
                             std::size_t k) {
  EXPECT_GT(reference["onsets_s"].size(), k);
  EXPECT_GT(lossy["onsets_s"].size(), k);
  if (reference["onsets_s"].size() <= k || lossy["onsets_s"].size() <= k) return {1e9, 0};
  return {lossy["onsets_s"][k].get<double>() - reference["onsets_s"][k].get<double>(),
          lossy["onset_uncertainty_s"][k].get<double>()};
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
      // LAME tag. libsndfile recognises MP3 too, but FFmpeg decodes it: it refuses a damaged
      // frame where mpg123 would resync past it.
      {"lame.mp3",
       {"-c:a", "libmp3lame", "-b:a", "128k"},
       "ffmpeg",
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
  const auto json = folder_ / "out.json";
  const auto result = RunBouncecal("analyze '" + (folder_ / "adts.aac").string() + "' --json '" +
                                   json.string() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("does not state its encoder delay"), std::string::npos)
      << result.output;
  EXPECT_EQ(ReadJson(json)["encoder_delay"], "unknown");
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

// The codec timing table (codec_timing.cc) and the response timing's own uncertainties
// (response_timing.h) were measured by bench/codec_timing_bench on seeds 1-16 of its own scenes;
// on other drops the shift of each onset of a high bit rate copy against the WAV's must still lie
// within 1.96 of the two onsets' stated sigmas in quadrature at the rate they promise (95 %,
// tested at 90 %: 4 drops give ~48 shifts, so two outliers more than expected must not fail it).
// A detector change that makes codec onsets worse fails here: re-run the bench and update the
// table.
TEST_F(CodecInput, OnsetShiftsOfHighBitRateCopiesStayWithinTheirStatedUncertainties) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> settings = {
      {"aac.m4a", {"-c:a", "aac", "-b:a", "128k"}},
      {"mp3.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}},
      {"vorbis.ogg", {"-c:a", "libvorbis", "-q:a", "5"}},
      {"opus.opus", {"-c:a", "libopus", "-b:a", "64k"}},
      {"mulaw.wav", {"-c:a", "pcm_mulaw"}},
      {"adpcm.wav", {"-c:a", "adpcm_ima_wav"}},
  };
  for (const auto& [name, options] : settings) {
    SCOPED_TRACE(name);
    int shifts = 0, within = 0;
    for (std::uint64_t seed = 101; seed <= 104; ++seed) {
      const auto drop = Drop(seed);
      const auto wav = WriteWav(folder_ / "drop.wav", drop);
      const auto path = Encode(wav, name, options);
      const auto wav_detection = audio::DetectImpactsInFile(wav);
      const auto detection = audio::DetectImpactsInFile(path);
      ASSERT_TRUE(detection.codec_timing.has_value());
      EXPECT_TRUE(detection.codec_timing->high_bit_rate);
      std::vector<double> drop_shifts;
      std::vector<double> drop_sigmas;  // the two onsets' stated sigmas in quadrature
      for (double truth : drop.BallImpactOnsetsS()) {
        const auto nearest = [&](const audio::FileDetection& d) {
          audio::Impact best{.onset_s = 1e9};
          for (const auto& impact : d.detection.impacts) {
            if (std::fabs(impact.onset_s - truth) < std::fabs(best.onset_s - truth)) best = impact;
          }
          return best;
        };
        const auto a = nearest(wav_detection), b = nearest(detection);
        if (std::fabs(a.onset_s - truth) < 5e-3 && std::fabs(b.onset_s - truth) < 5e-3) {
          drop_shifts.push_back(b.onset_s - a.onset_s);
          drop_sigmas.push_back(std::hypot(a.onset_uncertainty_s, b.onset_uncertainty_s));
        }
      }
      ASSERT_FALSE(drop_shifts.empty());
      auto sorted = drop_shifts;
      std::sort(sorted.begin(), sorted.end());
      const double median = sorted[sorted.size() / 2];
      for (std::size_t i = 0; i < drop_shifts.size(); ++i) {
        ++shifts;
        within += std::fabs(drop_shifts[i] - median) <= 1.96 * drop_sigmas[i] ? 1 : 0;
      }
    }
    EXPECT_GE(within, 0.9 * shifts) << within << " of " << shifts;
  }
}

// Issue 30: through the file path, an AAC 128k copy's onsets are timed from their responses and
// stated with the alignment's precision, not the codec table's 967 us, and that precision covers
// the error against the truth. Tolerances from the codec bench (16 seeds x 2 scenes at 48 kHz:
// error p95 16 us, median stated sigma 10 us, 100 % within 1.96 sigma; docs/codecs.md): the
// issue's targets (p95 <= 150 us, median stated <= 200 us) with coverage tested at 90 %, since
// 4 drops give ~48 onsets and two outliers more than expected must not fail it.
TEST_F(CodecInput, AnAacCopysOnsetsAreStatedWithTheirAlignmentsPrecisionWhichCoversTheirError) {
  std::vector<double> errors, sigmas;
  int covered = 0;
  for (std::uint64_t seed = 201; seed <= 204; ++seed) {
    const auto drop = Drop(seed);
    const auto path =
        Encode(WriteWav(folder_ / "drop.wav", drop), "drop.m4a", {"-c:a", "aac", "-b:a", "128k"});
    const auto file = audio::DetectImpactsInFile(path);
    ASSERT_TRUE(file.response_timing.has_value());
    std::vector<double> drop_errors, drop_sigmas;
    for (double truth : drop.BallImpactOnsetsS()) {
      const audio::Impact* best = nullptr;
      for (const auto& impact : file.detection.impacts) {
        if (std::fabs(impact.onset_s - truth) < 5e-3 &&
            (!best || std::fabs(impact.onset_s - truth) < std::fabs(best->onset_s - truth))) {
          best = &impact;
        }
      }
      if (!best) continue;
      drop_errors.push_back(best->onset_s - truth);
      drop_sigmas.push_back(best->onset_uncertainty_s);
    }
    ASSERT_GE(drop_errors.size(), 8u);
    auto sorted = drop_errors;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];  // a constant cancels in every interval
    for (std::size_t i = 0; i < drop_errors.size(); ++i) {
      errors.push_back(std::fabs(drop_errors[i] - median));
      sigmas.push_back(drop_sigmas[i]);
      covered += errors.back() <= 1.96 * sigmas.back() ? 1 : 0;
    }
  }
  std::sort(errors.begin(), errors.end());
  std::sort(sigmas.begin(), sigmas.end());
  EXPECT_LE(errors[errors.size() * 95 / 100], 150e-6);
  EXPECT_LE(sigmas[sigmas.size() / 2], 200e-6);
  EXPECT_GE(covered, 0.9 * static_cast<double>(errors.size()))
      << covered << " of " << errors.size();
}

TEST_F(CodecInput, AnAacCopyOfTheSteelSampleKeepsItsEtaBarAndSaysItIsLossy) {
  const fs::path sample = SourceDir() / "samples" / "steel_ball_h0.2m.wav";
  const auto m4a = folder_ / "steel.m4a";
  ASSERT_TRUE(EncodeWithFfmpeg(sample, m4a, {"-c:a", "aac", "-b:a", "128k"}));
  const auto wav_json = folder_ / "wav.json", m4a_json = folder_ / "m4a.json";
  ASSERT_EQ(RunBouncecal("analyze '" + sample.string() + "' --json '" + wav_json.string() + "'")
                .exit_status,
            0);
  const auto result =
      RunBouncecal("analyze '" + m4a.string() + "' --json '" + m4a_json.string() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto wav = ReadJson(wav_json), lossy = ReadJson(m4a_json);
  EXPECT_EQ(wav["lossy"], false);
  EXPECT_EQ(wav["codec_timing_uncertainty_s"], 0.0);
  EXPECT_EQ(lossy["codec"], "aac");
  EXPECT_EQ(lossy["container"], "m4a");
  EXPECT_EQ(lossy["lossy"], true);
  EXPECT_EQ(lossy["encoder_delay"], "removed");
  const double codec_sigma = lossy["codec_timing_uncertainty_s"];
  EXPECT_GT(codec_sigma, 0);
  // One warning line names the file, the codec and the added uncertainty.
  const std::string warning = "warning: " + m4a.string() + ": lossy aac";
  ASSERT_NE(result.output.find(warning), std::string::npos) << result.output;
  EXPECT_NE(
      result.output.find(std::to_string(static_cast<int>(std::lround(codec_sigma * 1e6))) + " us"),
      std::string::npos)
      << result.output;
  // The steel sample's impacts ring alike, so the response timing states most of them with the
  // alignment's precision instead of the codec's, and each impact says which: one not timed from
  // its response carries the codec's error in quadrature (at least that), and one stated below a
  // fifth of it can only have been timed from its response. (One the timing aligned may still
  // state more: half the distance to the detector's onset where the two disagree.)
  int own = 0;
  for (const auto& impact : lossy["impacts"]) {
    const double sigma = impact["onset_uncertainty_s"];
    if (!impact["timed_from_response"].get<bool>()) {
      EXPECT_GE(sigma, codec_sigma * (1 - 1e-12)) << impact.dump();
    } else if (sigma < 0.2 * codec_sigma) {
      ++own;
    }
  }
  EXPECT_GE(own, 4) << lossy["impacts"].dump();
  // The terminal table marks them too, with the legend once under the table.
  EXPECT_NE(result.output.find("a: timed from its whole response"), std::string::npos)
      << result.output;
  // Issue 18's done-when: eta-bar within 0.005 of the WAV's (the steel sample's first impacts
  // stand 20+ dB out of their tails, so AAC at 128 kbit/s moves them by a few samples at most).
  const double eta_wav = wav["sequences"][0]["energy_loss_mean_first_n"];
  const double eta_aac = lossy["sequences"][0]["energy_loss_mean_first_n"];
  EXPECT_NEAR(eta_aac, eta_wav, 0.005);
  // And the difference is within the stated uncertainties, no longer hidden by them.
  const double stated =
      std::hypot(wav["sequences"][0]["energy_loss_mean_first_n_uncertainty"].get<double>(),
                 lossy["sequences"][0]["energy_loss_mean_first_n_uncertainty"].get<double>());
  EXPECT_LE(std::fabs(eta_aac - eta_wav), 2 * stated);
}

// Telephone and voice-recorder rates (issue 30): a 16 kHz and an 8 kHz copy of the steel sample,
// resampled by ffmpeg (its default filter, as a phone app or a conversion would), and the 8 kHz
// copy in G.711 mu-law as a telephone line carries it. Each forms the sample's sequence, and its
// eta-bar stays within 0.005 of the WAV's, the bound. With eta = 1 - e^2 and e a ratio of
// flights, 0.005 in eta is 0.6 % of a flight ratio at e = 0.65: 0.4 ms on the shortest flight
// eta-bar uses (0.071 s), 3.4 samples at 8 kHz. The copies' eta-bar differ from the WAV's by 0.0003
// (16 kHz), 0.0007 (8 kHz) and 0.0010 (mu-law), measured 2026-12-02: the bound fails on a
// misplaced or missing impact, not on the rate's coarser timing.
TEST_F(CodecInput, TelephoneRateCopiesOfTheSteelSampleKeepItsSequenceAndEtaBar) {
  const fs::path sample = SourceDir() / "samples" / "steel_ball_h0.2m.wav";
  const auto wav_json = folder_ / "wav.json";
  ASSERT_EQ(RunBouncecal("analyze '" + sample.string() + "' --json '" + wav_json.string() + "'")
                .exit_status,
            0);
  const double eta_wav = ReadJson(wav_json)["sequences"][0]["energy_loss_mean_first_n"];
  const std::vector<std::pair<std::string, std::vector<std::string>>> copies = {
      {"steel_16k.wav", {"-ar", "16000"}},
      {"steel_8k.wav", {"-ar", "8000"}},
      {"steel_8k_mulaw.wav", {"-ar", "8000", "-c:a", "pcm_mulaw"}},
  };
  for (const auto& [name, options] : copies) {
    const fs::path copy = Encode(sample, name, options);
    const auto json_path = folder_ / (name + ".json");
    const auto result =
        RunBouncecal("analyze '" + copy.string() + "' --json '" + json_path.string() + "'");
    ASSERT_EQ(result.exit_status, 0) << name << "\n" << result.output;
    const auto analysis = ReadJson(json_path);
    ASSERT_FALSE(analysis["sequences"].empty()) << name << "\n" << result.output;
    const double eta = analysis["sequences"][0]["energy_loss_mean_first_n"];
    EXPECT_NEAR(eta, eta_wav, 0.005) << name;
  }
}

// Samples handed over in memory (the Python module's numpy path) take the response timing where
// a file of the same samples does (below 20 kHz), so both give the same onsets and sigmas. A
// float WAV holds the samples exactly, so the two agree bit for bit. Needs no ffmpeg.
TEST(RecordingAnalysisSamples, BelowTwentyKilohertzTheyAreRetimedAsTheirWavIs) {
  audio::SynthesisOptions options;
  options.sample_rate_hz = 16000;
  options.drop.drop_height_m = 0.25;
  options.drop.restitution.constant = 0.7;
  audio::NoiseOptions noise;
  noise.snr_db = 35;
  options.noise = noise;
  const auto synthesized = audio::SynthesizeBounces(options);
  const ScratchFolder folder;
  const auto wav = folder / "drop_16k.wav";
  audio::WriteRecording(wav, synthesized.channels,
                        {audio::AudioContainer::kWav, audio::SampleEncoding::kFloat});
  const auto from_file = calibrate::AnalyzeRecording(wav, {});
  const auto in_memory = calibrate::AnalyzeRecordingSamples(synthesized.channels[0], {});
  ASSERT_TRUE(from_file.detection.response_timing.has_value());
  ASSERT_TRUE(in_memory.detection.response_timing.has_value());
  EXPECT_GT(in_memory.detection.response_timing->aligned, 0);
  const auto& file_impacts = from_file.detection.detection.impacts;
  const auto& memory_impacts = in_memory.detection.detection.impacts;
  ASSERT_EQ(memory_impacts.size(), file_impacts.size());
  for (std::size_t i = 0; i < file_impacts.size(); ++i) {
    EXPECT_EQ(memory_impacts[i].onset_s, file_impacts[i].onset_s) << i;
    EXPECT_EQ(memory_impacts[i].onset_uncertainty_s, file_impacts[i].onset_uncertainty_s) << i;
  }
}

// The README's determinism promise holds for decoded input too: FFmpeg decodes on one thread,
// so the same M4A and MP3 give the same bytes of JSON every run.
TEST_F(CodecInput, AnalysingALossyFileTwiceWritesByteIdenticalJson) {
  const auto wav = WriteWav(folder_ / "drop.wav", Drop(9));
  for (const std::string name : {"drop.m4a", "drop.mp3"}) {
    SCOPED_TRACE(name);
    const auto encoded = Encode(wav, name, {"-b:a", "96k"});
    std::string runs[2];
    for (int run = 0; run < 2; ++run) {
      const auto json = folder_ / ("run" + std::to_string(run) + ".json");
      ASSERT_EQ(RunBouncecal("analyze '" + encoded.string() + "' --json '" + json.string() + "'")
                    .exit_status,
                0);
      std::ifstream in(json, std::ios::binary);
      runs[run].assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    EXPECT_FALSE(runs[0].empty());
    EXPECT_EQ(runs[0], runs[1]);
  }
}

TEST_F(CodecInput, TheCalibrationInputCarriesTheCodecErrorExactlyOnce) {
  const fs::path sample = SourceDir() / "samples" / "steel_ball_h0.2m.wav";
  const auto m4a = folder_ / "steel.m4a";
  ASSERT_TRUE(EncodeWithFfmpeg(sample, m4a, {"-c:a", "aac", "-b:a", "128k"}));
  const double sigma = audio::DetectImpactsInFile(m4a).codec_timing->onset_uncertainty_s;
  // The detector's onsets retimed from their responses, as the file path does for a lossy file,
  // from the same decoded samples: the codec's error is in every sigma the alignment did not
  // state, once.
  const auto recording = audio::LoadRecording(m4a);
  auto raw = audio::DetectImpacts(recording);
  audio::RetimeFromResponses(raw, recording.samples, sigma);
  audio::GroupBounces(raw);
  const auto sequences = calibrate::LoadSequences({m4a});
  ASSERT_FALSE(sequences.empty());
  EXPECT_EQ(sequences.front().lossy_codec, "aac");
  EXPECT_EQ(sequences.front().codec_timing_uncertainty_s, sigma);
  for (const auto& impact : sequences.front().impacts) {
    const auto same = std::find_if(raw.impacts.begin(), raw.impacts.end(), [&](const auto& r) {
      return std::fabs(r.onset_s - impact.onset_s) < 1e-9;
    });
    ASSERT_NE(same, raw.impacts.end()) << impact.onset_s;
    EXPECT_NEAR(impact.uncertainty_s, same->onset_uncertainty_s, 1e-12) << impact.onset_s;
  }
}

// calibrate (and report, through the same loader) says once per lossy file why its interval is
// wide, as analyze does: widened, not silently.
TEST_F(CodecInput, CalibratingALossyFileSaysOnceThatItsOnsetsWereWidened) {
  const fs::path sample = SourceDir() / "samples" / "steel_ball_h0.2m.wav";
  const auto m4a = folder_ / "steel.m4a";
  ASSERT_TRUE(EncodeWithFfmpeg(sample, m4a, {"-c:a", "aac", "-b:a", "128k"}));
  const auto lossy =
      RunBouncecal("calibrate '" + m4a.string() + "' --ball steel-10mm --drop-height-m 0.2");
  ASSERT_EQ(lossy.exit_status, 0) << lossy.output;
  const std::string warning = "warning: " + m4a.string() + ": lossy aac";
  const auto first = lossy.output.find(warning);
  ASSERT_NE(first, std::string::npos) << lossy.output;
  EXPECT_EQ(lossy.output.find(warning, first + 1), std::string::npos) << lossy.output;
  const auto lossless =
      RunBouncecal("calibrate '" + sample.string() + "' --ball steel-10mm --drop-height-m 0.2");
  ASSERT_EQ(lossless.exit_status, 0) << lossless.output;
  EXPECT_EQ(lossless.output.find("lossy"), std::string::npos) << lossless.output;
}

// Issue 16's example: a Vorbis copy of eeps-pingpong moved eta-bar by 20 times its stated
// uncertainty, silently. Now the stated uncertainty carries the codec's error.
TEST_F(CodecInput, AVorbisCopyOfEepsPingpongAgreesWithTheWavWithinItsStatedUncertainty) {
  const fs::path wav = SharedDir() / "recordings" / "eeps-pingpong" / "pingpong.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  // FFmpeg's default libvorbis quality (q3) and a lower one.
  for (const std::string quality : {"3", "2"}) {
    SCOPED_TRACE("q" + quality);
    const auto ogg =
        Encode(wav, "pingpong_q" + quality + ".ogg", {"-c:a", "libvorbis", "-q:a", quality});
    const auto [difference, stated] = CompareCopyWithItsWav(wav, ogg, folder_.path());
    // Two sigma: a consistent measurement, where before it was 8-20.
    EXPECT_LE(difference, 2 * stated) << difference << " vs " << stated;
  }
}

// Issue 30: a transform codec's pre-echo rose into a loud bounce from a fainter sound before it,
// and the merger kept that sound's onset (basketball.wav as MP3 at 24 kHz: the first onset 8.1 ms
// early, stated +-336 us, eta-bar 13 combined sigmas off; ub-mth337 pingpong.wav as Opus: the
// fifth 3.9 ms early, 3.1 sigmas). Such onsets now state half the distance to the louder rest of
// their sound (and where the rest is louder by the full rise threshold, take its onset: the next
// test). Three combined sigmas, the line for a confident wrong answer.
TEST_F(CodecInput, CopiesWhosePreEchoMovedAnOnsetStateAnUncertaintyThatCoversIt) {
  struct Copy {
    std::string recording, name;
    std::vector<std::string> options;
  };
  const std::vector<Copy> copies = {
      {"basketball.wav", "basketball.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}},
      {"pingpong.wav", "pingpong.opus", {"-c:a", "libopus", "-b:a", "64k"}}};
  for (const Copy& copy : copies) {
    SCOPED_TRACE(copy.name);
    const fs::path wav = SharedDir() / "recordings" / "ub-mth337" / copy.recording;
    if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
    const auto encoded = Encode(wav, copy.name, copy.options);
    const auto [difference, stated] = CompareCopyWithItsWav(wav, encoded, folder_.path());
    EXPECT_LE(difference, 3 * stated) << difference << " vs " << stated;
  }
}

// Issue 30 (phone rates): ub-mth337's ping-pong as MP3 64k and Vorbis q4 at 16 kHz began its
// sequence at three sounds of handling the ball, 42-61 dB under the drop's first bounce, whose
// flights (0.77, 0.72, 0.68 s) continued into the drop's (eta-bar 0.1873 and 0.1900 against the
// WAV's 0.1716, 17 and 22 combined sigmas, exit 0). Judged one by one against the next levels,
// which held their own, they were not quieter by the margin; all at once against the levels
// from the drop's first bounce on, they are, and are cut. 0.002: the line for a copy.
TEST_F(CodecInput, SixteenKilohertzCopiesOfUbPingpongDoNotStartAtTheHandlingBeforeTheDrop) {
  const fs::path wav = SharedDir() / "recordings" / "ub-mth337" / "pingpong.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto reference = FirstSequence(wav, folder_.path());
  const std::vector<std::pair<std::string, std::vector<std::string>>> copies = {
      {"pingpong_16k.mp3", {"-ar", "16000", "-c:a", "libmp3lame", "-b:a", "64k"}},
      {"pingpong_16k.ogg", {"-ar", "16000", "-c:a", "libvorbis", "-q:a", "4"}}};
  for (const auto& [name, options] : copies) {
    SCOPED_TRACE(name);
    ExpectTheWavsDrop(reference, FirstSequence(Encode(wav, name, options), folder_.path()), 1e-3,
                      0.002);
  }
}

// Issue 30 (phone rates): ub-mth337's basketball (a 24 kHz WAV) as AAC 128k at 44.1 kHz gave
// eta-bar 0.1644 against the WAV's 0.2937 (24 combined sigmas, exit 0). The codec left 254 events
// in the ringing tails that only the ringing residual found, and a chain through them from a sound
// 1.6 s before the drop ran on into the drop's last bounces: 25 members, 12 band-detected, longer
// than the drop's own 18 (16 band-detected), so it was tested first, and its timing on the drop's
// bounces passed (0.0037 expected chance chains). In a codec's file chains are now ranked by
// their band-detected members first. 0.002: the line for a copy; the first onset to 5 ms
// (the copy states it +-3.1 ms).
TEST_F(CodecInput, AnAacCopyOfBasketballAt44kHzIsTheDropNotTheCodecsEventsBeforeIt) {
  const fs::path wav = SharedDir() / "recordings" / "ub-mth337" / "basketball.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a =
      Encode(wav, "basketball_44k.m4a", {"-ar", "44100", "-c:a", "aac", "-b:a", "128k"});
  ExpectTheWavsDrop(FirstSequence(wav, folder_.path()), FirstSequence(m4a, folder_.path()), 5e-3,
                    0.002);
}

// Issue 30: in basketball.wav as MP3 128k the pre-echo joined a -27 dBFS sound 8.1 ms before the
// first bounce to the bounce, and the merger kept the fainter sound's onset (eta-bar 0.3000 +-
// 0.0051 against the WAV's 0.2937). A rest of the sound louder by the full rise threshold over
// the same span is the hit, as the WAV's merger decided: the first onset is the WAV's. Tolerances:
// 0.5 ms is well under the 8.1 ms between the two sounds; 0.002 is the line for a copy.
TEST_F(CodecInput, AnMp3CopyOfBasketballTimesTheBounceThePreEchoJoinedToTheSoundBeforeIt) {
  const fs::path wav = SharedDir() / "recordings" / "ub-mth337" / "basketball.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto mp3 = Encode(wav, "basketball_first.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(mp3, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  EXPECT_NEAR(lossy["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), 5e-4);
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
}

// Issue 30: alessia rimbalzi as AAC 128k (64 kbit/s per channel) gave eta-bar 0.8376 +- 0.004
// against the WAV's 0.2065, 150 combined sigmas: a chain through the codec's per-frame
// residual-only events beside the real bounces passed the chance test at the file's average rate
// of such events, took the real sequence's middle, and left its first impacts to a chain with
// two faint sounds. Counted at one per frame, that chain is chance and the real sequence stands.
// Three combined sigmas, the line for a confident wrong answer (it lies at 0.4).
TEST_F(CodecInput, AnAacCopyOfAlessiaRimbalziKeepsTheWavsSequence) {
  const fs::path wav = SharedDir() / "recordings" / "alessia-rimbalzi" / "rimbalzi.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "rimbalzi.m4a", {"-c:a", "aac", "-b:a", "128k"});
  const auto [difference, stated] = CompareCopyWithItsWav(wav, m4a, folder_.path());
  EXPECT_LE(difference, 3 * stated) << difference << " vs " << stated;
}

// Issue 30: zaky-ptv's pingpongvid2 as MP3 128k put its 4th bounce 1.19 ms early, stated +-253
// us (eta-bar 0.2496 against the WAV's 0.2539, 4.4 combined sigmas). Its pick window reached back
// over a rise just before the bounce that a separate candidate bounds in the WAV, and the band
// envelopes, which put it 0.86 ms later, were called ambiguous: a wiggle of 0.005 on the flank of
// their peak (0.510) was taken for a rival 0.105 below it. A rival must now rise out of a dip the
// bands resolve: the onset is the envelopes' (328 us early, +-229 us) and eta-bar 0.2517 (2.3
// sigmas; most of the rest is the 5th onset, where the WAV states 1.550004 s +-272 us and both
// this copy and the Opus copy 1.550635 s).
TEST_F(CodecInput, AnMp3CopyOfZakyPingpongRetimesTheBounceItsPickWindowTookEarly) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto mp3 = Encode(wav, "pingpongvid2.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(mp3, folder_.path());
  const auto [error, stated] = CompareOnsets(reference, lossy, 3);
  EXPECT_LE(std::fabs(error), 3 * stated) << error << " vs " << stated;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: zaky-ptv's ping-pong as AAC 128k (speech throughout) formed no sequence: the longest
// chain took every other bounce (its ratios e^2 = 0.75), heard sounds sat where 6 of its 12
// skipped bounces would be, so it was refused, and nothing took the drop. The chain through the
// skipped bounces is now its sequence; the speech sound before it (0.011 s, stated +-1.6 ms,
// 12 dB under the first bounce) is judged by its level as it is in the WAV. eta-bar 0.0027 from
// the WAV's, 1.7 combined sigmas.
TEST_F(CodecInput, AnAacCopyOfZakyPingpongIsTheChainThroughTheBouncesItsLongestChainSkipped) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "pingpongvid2.m4a", {"-c:a", "aac", "-b:a", "128k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  EXPECT_NEAR(lossy["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), 2e-3);
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.003) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: the clip's video (60 fps) shows the ball on the table at frames 10-11, 34-35 and
// 54-55, which are the audio's 0.0450, 0.4452 and 0.7862 s sounds (docs/codecs.md). The WAV's
// sequence began at 0.4452 s: its first bounce rose 9.1 dB in the bands while speech's sibilants
// filled the 12 ms before it above 2 kHz, and counted as heard only in the ringing. It rises by
// the full threshold below 2 kHz (the low band) and starts the sequence; its eta-bar then agrees
// with the copy low-passed at 3 kHz, which has no sibilants to hide it (0.2632 +- 0.0004).
TEST_F(CodecInput, ZakyPingpongsWavStartsAtTheFirstBounceItsVideoShows) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto sequence = FirstSequence(wav, folder_.path());
  ASSERT_FALSE(sequence.is_null());
  // 1 ms: well under the 0.40 s flight to the next bounce, well over any onset error.
  EXPECT_NEAR(sequence["onsets_s"][0].get<double>(), 0.0450, 1e-3);
  const auto copy =
      Encode(wav, "pingpongvid2_lowpass3k.wav", {"-af", "lowpass=f=3000", "-c:a", "pcm_s16le"});
  const auto [difference, combined] =
      CompareSequences(FirstSequence(copy, folder_.path()), sequence);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30 (sequences at 16 kHz): zaky-ptv's ping-pong resampled to 16 kHz gave eta-bar 0.3809
// +- 0.0004 against the WAV's 0.2527 (168 combined sigmas, exit 0). Its 2nd, 5th and 7th bounces
// follow sounds of the room 15-26 ms before them; without the bands above 8 kHz they rose too
// little and were heard only in the ringing, their responses aligned to the first bounce's at rho
// 0.68-0.78, short of the 0.8 that confirms in a full-band WAV, and a chain of the room's sounds
// with the ball's first bounce took the drop's place. Below 20 kHz every usable alignment now
// confirms, as in a transform codec's file. 3 combined sigmas and the 0.005 for
// telephone-rate copies (now 0.0019, 1.3 sigmas).
TEST_F(CodecInput, ASixteenKilohertzCopyOfZakyPingpongIsTheDropNotTheRoomsSounds) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto copy = Encode(wav, "pingpongvid2_16k.wav", {"-ar", "16000", "-c:a", "pcm_s16le"});
  ExpectTheWavsDrop(FirstSequence(wav, folder_.path()), FirstSequence(copy, folder_.path()), 1e-3,
                    0.005);
}

// Issue 30: zaky-ptv's ping-pong as Opus 64k and Vorbis q4 (Debian's ffmpeg 5.1) gave eta-bar
// 0.4445 +- 0.0013 (132 combined sigmas from the WAV's 0.2539) and 0.3305 +- 0.015 (5.0), exit 0.
// A chain of the ball's chatter after 2.59 s (ratios 0.56-1.2), every member band-detected and
// passing over no louder sound, was exempt from the chance test, and the Opus copy's was then
// tracked back along every other bounce (sounds where 4 of its skipped bounces would be, by chance
// at 4.3e-4, above the 1e-4 that refuses). In a transform codec's file band-detected events are
// also the codec's, so there such a chain must at least not time like chance (random events
// match these chatter chains 8.9-407 times over): both copies now report no eta-bar (the Opus
// copy three of the WAV's bounces). A right eta-bar or none is honest; a confident wrong one is
// not. Debian's ffmpeg 5.1.9 encodes an Opus copy whose chain's head, two sounds 12 dB under the
// drop, stood in for its first bounce: cut as quieter, they left the chain from the second bounce
// (0.2418 +- 0.0034, 3.2 combined sigmas) until the chain left was tracked back again (0.2486).
TEST_F(CodecInput, OpusAndVorbisCopiesOfZakyPingpongGiveTheWavsEtaBarOrNoneNotTheirChatters) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto reference = FirstSequence(wav, folder_.path());
  const std::vector<std::pair<std::string, std::vector<std::string>>> copies = {
      {"pingpongvid2.opus", {"-c:a", "libopus", "-b:a", "64k"}},
      {"pingpongvid2.ogg", {"-c:a", "libvorbis", "-q:a", "4"}}};
  for (const auto& [name, options] : copies) {
    SCOPED_TRACE(name);
    const auto lossy = FirstSequence(Encode(wav, name, options), folder_.path());
    if (lossy.is_null() || !lossy["energy_loss_mean_first_n"].is_number()) continue;
    const auto [difference, combined] = CompareSequences(reference, lossy);
    EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
  }
}

// Issue 30 (telephone rates): zaky-ptv's ping-pong as G.711 mu-law at 8 kHz gave eta-bar 0.4579 +-
// 0.027 against the WAV's 0.2527 (7.5 combined sigmas, exit 0). The codec's noise made 74 impacts
// of the file's sounds, the drop's chains timed like chance among them, and a five-member chain
// of the ball's last bounces took its place, its first flight over a bounce nobody heard: ratio
// 0.4055 (e^2 / (1 + e) = 0.394 for e = 0.855), then 0.857 and 0.853. Its first member is now a
// sound before the drop (ShortChainsFirstFlightMisfits), and four members give no eta-bar.
TEST_F(CodecInput, AMuLawCopyOfZakyPingpongAtEightKilohertzGivesTheWavsEtaBarOrNone) {
  const fs::path wav =
      SharedDir() / "recordings" / "zaky-ptv-pingpong" / "pingpongvid2_48k_mono.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto copy = Encode(wav, "pingpongvid2_mulaw.wav", {"-ar", "8000", "-c:a", "pcm_mulaw"});
  const auto lossy = FirstSequence(copy, folder_.path());
  if (lossy.is_null() || !lossy["energy_loss_mean_first_n"].is_number()) return;
  const auto [difference, combined] = CompareSequences(FirstSequence(wav, folder_.path()), lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: an impact timed from its band envelopes combined them with the detector's onset
// weighted by the detector's own sigma alone (+-30 us), so in eeps-pingpong.wav as Vorbis q4 the
// first bounce kept its pre-echo-shifted first lobe (746 us before the WAV's onset, stated
// +-428 us) and eta-bar lay 0.0024 from the WAV's. With the codec table's sigma in quadrature, as
// the waveform stage weighs it, the first onset is 286 us early and eta-bar 0.0003 off.
TEST_F(CodecInput, AVorbisCopyOfEepsPingpongWeighsItsPreEchoedOnsetsByTheCodecsError) {
  const fs::path wav = SharedDir() / "recordings" / "eeps-pingpong" / "pingpong.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto ogg = Encode(wav, "pingpong_q4.ogg", {"-c:a", "libvorbis", "-q:a", "4"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(ogg, folder_.path());
  const auto [error, stated] = CompareOnsets(reference, lossy, 0);
  EXPECT_LE(std::fabs(error), stated) << error << " vs " << stated;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  // The line for a lossy copy.
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
}

// Issue 30: fr4nci Audio_1.wav as Vorbis q4 formed no sequence. The chain search keeps the best
// chain from each first impact, longest first, and from the drop's first bounce that was a chain
// of 2 band-detected impacts 1.65 s apart and 5 residual-only sounds of the codec's noise (7
// members against the drop's 6 band-detected bounces); the chance test refused it (9.8 expected
// chance chains) and the drop's own chain was never tried. Now the next chains from that impact
// answer to the test (each counted against it): the copy gives the WAV's eta-bar.
TEST_F(CodecInput, AVorbisCopyOfFr4nciAudio1FindsTheDropBehindAChanceChainFromItsFirstBounce) {
  const fs::path wav = SharedDir() / "recordings" / "fr4nci-rimbalzi" / "Audio_1.wav";
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto ogg = Encode(wav, "audio_1_q4.ogg", {"-c:a", "libvorbis", "-q:a", "4"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(ogg, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  ASSERT_TRUE(lossy["energy_loss_mean_first_n"].is_number()) << lossy.dump();
  const auto [difference, combined] = CompareSequences(reference, lossy);
  // The line for a lossy copy, and covered by the stated uncertainties.
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// The detector suite's recordings (an independent generator's, exact truth) as the held-out
// recordings' copies are encoded, by path beside the project (skipped where it is absent).
fs::path DetectorSuiteRecording(const std::string& name) {
  return SharedDir() / "detector-suite" / "recordings" / name;
}

// Issue 30: multi_drop_30s as Opus 64k lost its first drop: the chain of its 4 band-detected
// bounces took a codec sound 10.8 ms before where its 6th bounce was due and then read as chance
// (FindBounceSequences), so the first sequence was the second drop's (eta-bar 0.5599 against the
// WAV's 0.5425, 56 combined sigmas as `shared_codec_eta.py` pairs first sequences). The chain now
// ends before that sound.
TEST_F(CodecInput, AnOpusCopyOfTheSuitesThreeDropsKeepsItsFirstDrop) {
  const fs::path wav = DetectorSuiteRecording("multi_drop_30s.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto opus = Encode(wav, "multi_drop_30s.opus", {"-c:a", "libopus", "-b:a", "64k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(opus, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  EXPECT_NEAR(lossy["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), 2e-3);
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: knock_speech_before as Opus 48k timed its 5th bounce on a faint sound 7.7 ms before
// it (residual-only, +-1.8 ms): the bounce's pre-echo had opened a candidate there and held the
// ringing residual's novelty over the secondary threshold until the bounce, so the bounce never
// opened one of its own, and eta-bar read 0.5811 against the WAV's 0.5507 (3.0 combined sigmas,
// exit 0). A novelty the full threshold above the closed candidate's, after a dip, now opens a
// candidate (CandidateTracker::Step): 0.5504.
TEST_F(CodecInput, AnOpusCopyOfKnockSpeechBeforeFindsTheBounceItsPreEchoHid) {
  const fs::path wav = DetectorSuiteRecording("knock_speech_before.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto opus = Encode(wav, "knock_speech_before.opus", {"-c:a", "libopus", "-b:a", "48k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(opus, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  const auto fifth = CompareOnsets(reference, lossy, 4);
  EXPECT_LE(std::fabs(fifth.error), fifth.stated) << fifth.error << " vs " << fifth.stated;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
}

// Issue 30: pingpong_table as AAC 128k began its sequence at a room reflection 15.7 ms after the
// first bounce, detected as a sound of its own and 1.5 dB louder (e_1 0.8925 against the WAV's
// 0.8616, eta-bar 0.0181 off at 6.4 combined sigmas, exit 0). The first ratio now chooses the
// sound that continues the drop's line of ratios (FirstMemberThatFitsTheDrop).
TEST_F(CodecInput, AnAacCopyOfTheSuitesPingpongStartsAtItsFirstBounceNotItsReflection) {
  const fs::path wav = DetectorSuiteRecording("pingpong_table.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "pingpong_table.m4a", {"-c:a", "aac", "-b:a", "128k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  EXPECT_NEAR(lossy["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), 2e-3);
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: the same copy's reflection, 1.5 dB louder than the first bounce, was also the response
// timing's template; every bounce correlated with it at rho 0.50-0.60 and 30 of the 33 members
// kept the AAC table's +-967 us (eta-bar +-0.0028 against the WAV's +-0.00003). The template is
// now the loudest impact that half of the loud others align with: the bounces are stated with
// their alignment's precision. 100 us: the median stated onset sigma is now 31 us, and AAC's
// line in the issue is 200 us; 0.002: the issue's line for eta-bar.
TEST_F(CodecInput, AnAacCopyOfTheSuitesPingpongAlignsItsBouncesToABounceNotTheReflection) {
  const fs::path wav = DetectorSuiteRecording("pingpong_table.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "pingpong_table_template.m4a", {"-c:a", "aac", "-b:a", "128k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  auto sigmas = lossy["onset_uncertainty_s"].get<std::vector<double>>();
  ASSERT_GE(sigmas.size(), 20u);
  std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
  EXPECT_LT(sigmas[sigmas.size() / 2], 100e-6);
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: very_high_e as AAC 64k at 16 kHz (a 64 ms frame at that rate) read eta-bar 0.1410
// +- 0.0047 against the WAV's 0.1057, 7.6 combined sigmas: its 5th bounce, 9.2 dB louder than
// the pre-echo that began 10.9 ms before it, lost the merge to it because the pre-echo raised the
// ringing residual more, and the sequence took it. Between in-ringing members that far apart in
// level the louder now keeps the onset (EventMerger): the sequence holds the WAV's 5th onset, not
// the pre-echo's. (Its first onset, 6.7 ms early on pre-echo too, now states +-3.9 ms and stays
// in the sequence: eta-bar 0.1178 +- 0.0067.)
TEST_F(CodecInput, AnAacCopyAtSixteenKilohertzTimesABounceNotThePreEchoBeforeIt) {
  const fs::path wav = DetectorSuiteRecording("very_high_e.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a =
      Encode(wav, "very_high_e_16k.m4a", {"-ar", "16000", "-c:a", "aac", "-b:a", "64k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  const double fifth = reference["onsets_s"][4].get<double>();
  double nearest = 1;
  for (const auto& onset : lossy["onsets_s"]) {
    nearest = std::min(nearest, std::fabs(onset.get<double>() - fifth));
  }
  EXPECT_LT(nearest, 1e-3) << "the WAV's 5th onset " << fifth;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30 (sequences at 16 kHz): the suite's sr96000 resampled to 16 kHz formed no sequence:
// every bounce after the first was heard only in the ringing residual, and such a sound never
// made a chain's second member. It does now where no band-detected one does
// (FindBounceSequences, a chance-test family of its own at a hundredth of the level).
TEST_F(CodecInput, ASixteenKilohertzCopyOfARingingDropKeepsItsSequence) {
  const fs::path wav = DetectorSuiteRecording("sr96000.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto copy = Encode(wav, "sr96000_16k.wav", {"-ar", "16000", "-c:a", "pcm_s16le"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto resampled = FirstSequence(copy, folder_.path());
  ASSERT_FALSE(resampled.is_null());
  EXPECT_NEAR(resampled["onsets_s"][0].get<double>(), reference["onsets_s"][0].get<double>(), 1e-3);
  const auto [difference, combined] = CompareSequences(reference, resampled);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
  // The line for telephone-rate copies.
  EXPECT_LE(difference, 0.005) << difference << " vs " << combined;
}

// Issue 30: steel_ref as AAC 64k at 22.05 kHz put its 2nd bounce 6.6 ms early, stated +-1.4 ms
// (eta-bar 0.5493 against the WAV's 0.5567, 3.7 combined sigmas): the codec's pre-echo rose into
// the attack without a break, so no merged event showed it. Its first millisecond stays 10 dB
// and more under the attack, and such an onset now states half the distance to where the attack
// begins (later_attack.h).
TEST_F(CodecInput, AnAacCopyAt22KilohertzStatesThePreEchoItsOnsetMayBe) {
  const fs::path wav = DetectorSuiteRecording("steel_ref.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "steel_ref_22k.m4a", {"-ar", "22050", "-c:a", "aac", "-b:a", "64k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: stereo as AAC 96k gave eta-bar 0.6453 +- 0.0067 against the WAV's 0.5505 (14
// combined sigmas, exit 0): its sequence took a residual-only codec sound 28 ms before the 5th
// bounce (FindBounceSequences: a residual-only sound now joins within the ratio's scatter and
// timing in quadrature). A right eta-bar or none.
TEST_F(CodecInput, AnAacCopyOfTheSuitesStereoDropGivesItsEtaBarOrNone) {
  const fs::path wav = DetectorSuiteRecording("stereo.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "stereo_96k.m4a", {"-c:a", "aac", "-b:a", "96k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(m4a, folder_.path());
  ExpectTheWavsEtaBarOrNone(reference, lossy, 3);
}

// Issue 30: reverb_strong as Opus 64k formed no sequence: its drop's 2 band-detected bounces and
// 4 found only in the ringing, each 3-4 ms from a prediction its rising e moves, timed like chance
// (0.44) with the codec's residual-only sounds counted at one per 20 ms frame, where its tails
// held 3 beside the drop over 0.7 s. Counted at the rate its span shows: the WAV's eta-bar
// (0.5503 against 0.5501).
TEST_F(CodecInput, AnOpusCopyOfTheSuitesReverbStrongDropKeepsItsSequence) {
  const fs::path wav = DetectorSuiteRecording("reverb_strong.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto opus = Encode(wav, "reverb_strong.opus", {"-c:a", "libopus", "-b:a", "64k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(opus, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  ASSERT_TRUE(lossy["energy_loss_mean_first_n"].is_number());
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// Issue 30: knock_speech_before as AAC 128k gave eta-bar 0.5385 against the WAV's 0.5507: its 5th
// bounce, in the ringing of the 4th, was picked right (18 us) but lost the merge to a part of its
// own sound 2.8 ms later, 2.7 dB louder in the band above 6 kHz. The sequence's interval ratios
// take the earlier onset back (TakeMergedOnsetsThatFitTheSequence): 0.5506.
TEST_F(CodecInput, AnAacCopyOfTheSuitesKnockDropKeepsTheBounceTheMergerLost) {
  const fs::path wav = DetectorSuiteRecording("knock_speech_before.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto m4a = Encode(wav, "knock_speech_before.m4a", {"-c:a", "aac", "-b:a", "128k"});
  ExpectTheWavsEtaBar(FirstSequence(wav, folder_.path()), FirstSequence(m4a, folder_.path()),
                      0.002);
}

// silent_wrong_sweep.py seed 9 #27: a 35 us contact on a counter at 96 kHz, 20 dB SNR to the
// weakest bounce, through a linear-phase chain, as MP3 64k. Its 2nd bounce, aligned on its
// response (stated +-10 us), had won the merge over a sound 6.5 ms before it; the sequence's
// ratios, on a line that its last, in-ringing member (+-1.9 ms) tilted, preferred that sound,
// and the aligned onset was taken for one the response timing had not seen (it had not moved
// it). eta-bar 0.3304 +- 0.0023 against the WAV's and the exact 0.3455, exit 0.
TEST_F(CodecInput, AnMp3CopyKeepsABounceItsResponseTimedAgainstAnEarlierSound) {
  const fs::path wav = folder_ / "counter_96k.wav";
  const auto synth = RunBouncecal(
      "synth -o '" + wav.string() +
      "' --sample-rate-hz 96000 --contact-duration-s 3.5e-05 --surface counter "
      "--restitution 0.809 --drop-height-m 0.095 --seed 28 --snr-db 20 --snr-reference weakest "
      "--adc linear-phase --level-jitter-db 3 --noise-color pink");
  ASSERT_EQ(synth.exit_status, 0) << synth.output;
  const auto mp3 = Encode(wav, "counter_96k.mp3", {"-c:a", "libmp3lame", "-b:a", "64k"});
  const auto [difference, combined] = CompareCopyWithItsWav(wav, mp3, folder_.path());
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
  EXPECT_LE(difference, 3 * combined) << difference << " vs " << combined;
}

// The suite's hum_dc as 8 kHz G.711 mu-law: its 60 Hz hum is heard as impacts every 16.7 ms (73
// of 92 impacts one or two periods from another), and chains along that lattice formed a sequence
// of ratios 1.000 (eta-bar -0.0054 against the WAV's 0.5503, 54 sigmas, exit 0). No chain along
// it is a sequence now: the copy gives no eta-bar (the drop's fourth bounce lies past a louder
// sound, which the hum makes chance), names the period and says why.
TEST_F(CodecInput, AMuLawCopyOfTheSuitesHumFileFormsNoSequenceAlongTheHum) {
  const fs::path wav = DetectorSuiteRecording("hum_dc.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto copy = Encode(wav, "hum_dc_mulaw.wav", {"-ar", "8000", "-c:a", "pcm_mulaw"});
  const auto json = folder_.path() / "hum_dc_mulaw.json";
  const auto run = RunBouncecal("analyze '" + copy.string() + "' --json '" + json.string() + "'");
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const auto recording = ReadJson(json);
  for (const auto& sequence : recording["sequences"]) {
    // Whatever sequence forms must be the drop's: within 0.005 of the WAV's (the line
    // at 8 kHz), never the hum's eta-bar near 0.
    EXPECT_NEAR(sequence["energy_loss_mean_first_n"].get<double>(), 0.5503, 0.005);
  }
  ASSERT_TRUE(recording["periodic_sound"].is_object());
  // The hum's events at 8 kHz sit up to 0.2 ms off its lattice; their period is 1/60 s within
  // a few hundredths of a ms.
  EXPECT_NEAR(recording["periodic_sound"]["period_s"].get<double>(), 1.0 / 60, 5e-5);
  EXPECT_NE(run.output.find("repeat every 16.6"), std::string::npos) << run.output;
  // The WAV has no periodic sound among its impacts.
  const auto wav_json = folder_.path() / "hum_dc.json";
  ASSERT_EQ(
      RunBouncecal("analyze '" + wav.string() + "' --json '" + wav_json.string() + "'").exit_status,
      0);
  EXPECT_TRUE(ReadJson(wav_json)["periodic_sound"].is_null());
}

// Issue 30: the suite's steel_ref as Opus 32k at 16 kHz (a messenger's voice note) found every
// bounce of its drop but formed no sequence: the codec's noise before the 2nd bounce held its band
// rise to 9.3 dB (residual-only), and its response, aligned to the first bounce's at rho 0.67,
// stayed short of the WAV's confirming 0.8; the chain then answered as one whose second impact
// only the ringing found (a hundredth of the test's level). In a transform codec's file every
// usable alignment confirms: the WAV's eta-bar (0.5567 against 0.5567). 0.002: the line.
TEST_F(CodecInput, AMessengerOpusCopyOfTheSuitesSteelDropFormsItsSequence) {
  const fs::path wav = DetectorSuiteRecording("steel_ref.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto opus =
      Encode(wav, "steel_ref_16k.opus", {"-ar", "16000", "-c:a", "libopus", "-b:a", "32k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(opus, folder_.path());
  ASSERT_FALSE(lossy.is_null());
  ASSERT_TRUE(lossy["energy_loss_mean_first_n"].is_number());
  const auto second = CompareOnsets(reference, lossy, 1);
  EXPECT_LE(std::fabs(second.error), 1.96 * second.stated)
      << second.error << " vs " << second.stated;
  const auto [difference, combined] = CompareSequences(reference, lossy);
  EXPECT_LE(difference, 0.002) << difference << " vs " << combined;
}

// Issue 30: with every usable alignment confirming (above), knock_speech_before in the same coding
// formed a sequence of its four band-detected bounces and a residual-only sound 7.5 ms before the
// unheard 5th (eta-bar 0.5807 against the WAV's 0.5507, 2.9 combined sigmas, exit 0): a
// band-detected chain in a codec's file met only the loose test for the codec's own rises. Its
// residual-only end must now time better than chance as well, and is cut where it does not. A
// right eta-bar or none; 2 combined sigmas, since the error above sat at 2.9.
TEST_F(CodecInput, AMessengerOpusCopyOfTheSuitesKnockDropEndsNotAtAPreEcho) {
  const fs::path wav = DetectorSuiteRecording("knock_speech_before.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto opus = Encode(wav, "knock_speech_before_16k.opus",
                           {"-ar", "16000", "-c:a", "libopus", "-b:a", "32k"});
  const auto reference = FirstSequence(wav, folder_.path());
  const auto lossy = FirstSequence(opus, folder_.path());
  ExpectTheWavsEtaBarOrNone(reference, lossy, 2);
}

// Issue 30: a bounce heard only in the ringing whose envelopes aligned was stated with the
// envelopes' sigma alone: multi_drop_30s as AAC 64k at 16 kHz put one 2.6 ms early at +-240 us
// (10.8 sigmas). Such a member now keeps at least the detector's own sigma. Every member of every
// sequence against the generator's exact onsets, less their median offset (only relative times
// enter intervals): within 3 stated sigmas (a 3-sigma miss happens 0.3 % of the time for a
// normal error; 25 members).
TEST_F(CodecInput, AnAacCopyAt16kHzStatesEveryBounceWithinThreeSigmasOfTheTruth) {
  const fs::path wav = DetectorSuiteRecording("multi_drop_30s.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  std::ifstream truth_file(DetectorSuiteRecording("multi_drop_30s.json"));
  const auto truth = nlohmann::json::parse(truth_file)["impact_times_s"];
  const auto m4a =
      Encode(wav, "multi_drop_30s_16k.m4a", {"-ar", "16000", "-c:a", "aac", "-b:a", "64k"});
  const auto json = folder_.path() / "multi_drop_30s_16k.json";
  ASSERT_EQ(
      RunBouncecal("analyze '" + m4a.string() + "' --json '" + json.string() + "'").exit_status, 0);
  std::vector<std::pair<double, double>> errors;  // onset minus the nearest true onset, sigma
  const auto recording = ReadJson(json);
  for (const auto& sequence : recording["sequences"]) {
    for (std::size_t k = 0; k < sequence["onsets_s"].size(); ++k) {
      const double onset = sequence["onsets_s"][k].get<double>();
      double nearest = truth[0].get<double>();
      for (const auto& t : truth) {
        if (std::fabs(t.get<double>() - onset) < std::fabs(nearest - onset))
          nearest = t.get<double>();
      }
      errors.emplace_back(onset - nearest, sequence["onset_uncertainty_s"][k].get<double>());
    }
  }
  ASSERT_GE(errors.size(), 20u);
  std::vector<double> sorted;
  for (const auto& e : errors) sorted.push_back(e.first);
  std::sort(sorted.begin(), sorted.end());
  const double offset = sorted[sorted.size() / 2];
  for (const auto& [error, sigma] : errors) {
    EXPECT_LE(std::fabs(error - offset), 3 * sigma) << error - offset << " s at +-" << sigma;
  }
}

// silent_wrong_sweep.py seed 919 #105: a dead ball (e 0.325) in a 0.5 s room, as AAC 96k. The cut
// that ended the recording, with the room's reverb still going, became a band-detected sound 8.6
// ms before the decoded end, and with the first bounce and the sounds the codec left in the reverb
// ~128 ms apart it made a sequence of 10 (eta-bar 0.12 +- 0.06 against the ball's 0.89, exit 0).
// Nothing in the stream's last two codec frames is taken for a bounce: the copy has no sequence,
// as its WAV has none, and that sound is rejected as the end's.
TEST_F(CodecInput, TheCutThatEndsAnAacStreamIsNoBounce) {
  const fs::path wav = folder_ / "dead_ball_room.wav";
  const auto synth = RunBouncecal(
      "synth -o '" + wav.string() +
      "' --sample-rate-hz 48000 --contact-duration-s 0.0008 --surface plate --restitution 0.325 "
      "--drop-height-m 0.209 --seed 106 --snr-db 30 --snr-reference weakest --reverb-rt60-s 0.50 "
      "--band-limit-hz 15905 --echo-delay-s 0.0055 --echo-gain-db -9 --noise-color pink");
  ASSERT_EQ(synth.exit_status, 0) << synth.output;
  const auto m4a = Encode(wav, "dead_ball_room.m4a", {"-c:a", "aac", "-b:a", "96k"});
  const auto json = folder_.path() / "dead_ball_room.json";
  ASSERT_EQ(
      RunBouncecal("analyze '" + m4a.string() + "' --json '" + json.string() + "'").exit_status, 0);
  const auto recording = ReadJson(json);
  EXPECT_TRUE(recording["sequences"].empty()) << recording["sequences"].dump();
  const double end_s = recording["duration_s"].get<double>();
  bool end_sound_rejected = false;
  for (const auto& event : recording["rejected_events"]) {
    if (event["time_s"].get<double>() > end_s - 0.02 &&
        event["reason"].get<std::string>().find("end of the lossy stream") != std::string::npos) {
      end_sound_rejected = true;
    }
  }
  EXPECT_TRUE(end_sound_rejected) << recording["rejected_events"].dump();
}

// Issue 30: where a transform codec spends no bits (the quiet after a drop), it empties whole
// bands, and from one of its frames to the next their near-zero residues rise by 20-34 dB, 60-160
// dB under the noise: the ringing residual read them as new sound, and the Vorbis q4 copy of the
// synthesiser's default drop 50 dB over white noise held 8 "impacts" in the second after its last
// bounce (its WAV none; the shared Palla-audio.wav's AAC copy: 173 impacts against the WAV's 17).
// A bin's rise is now measured from no less than a floor 20 dB under the noise
// (ringing_residual.cc).
TEST_F(CodecInput, TheQuietAfterADropHoldsNoImpactsInItsLossyCopies) {
  const fs::path wav = folder_ / "quiet_tail.wav";
  const auto synth = RunBouncecal("synth -o '" + wav.string() + "' --snr-db 50 --seed 1");
  ASSERT_EQ(synth.exit_status, 0) << synth.output;
  const auto last_bounce_s = [&] {
    const auto json = folder_.path() / "quiet_tail_wav.json";
    EXPECT_EQ(
        RunBouncecal("analyze '" + wav.string() + "' --json '" + json.string() + "'").exit_status,
        0);
    const auto onsets = ReadJson(json)["sequences"][0]["onsets_s"];
    return onsets.back().get<double>();
  }();
  for (const auto& [name, options] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"quiet_tail.ogg", {"-c:a", "libvorbis", "-q:a", "4"}},
           {"quiet_tail.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}}}) {
    const auto copy = Encode(wav, name, options);
    const auto json = folder_.path() / (name + ".json");
    ASSERT_EQ(
        RunBouncecal("analyze '" + copy.string() + "' --json '" + json.string() + "'").exit_status,
        0);
    const auto recording = ReadJson(json);
    ASSERT_FALSE(recording["impacts"].empty()) << name;
    // The sequence's own late members lie within a bounce flight (tens of ms) of its last one.
    for (const auto& impact : recording["impacts"]) {
      EXPECT_LT(impact["onset_s"].get<double>(), last_bounce_s + 0.05) << name;
    }
  }
}

// Issue 30: reverb_strong as MP3 128k, AAC 128k and Vorbis q4 formed no sequence (the WAV:
// 0.5501). Inside the room's loud reverberation the MP3 encoder leaves out its bands above 16 kHz
// and codes them again as its bit allocation moves: from 35-46 dB under the median bin they rose
// by 20-31 dB, the ringing residual's novelty reached 0.9-1.5 dB, and the copy held 11 impacts
// against the WAV's 7, with which the bounces heard only in the ringing timed like chance. A
// candidate that no band carried and that rose only in the bands the codec coded again is now no
// sound (RingingResidual::CodecNoveltyDb). The AAC and Vorbis encoders' long blocks spread a
// bounce's noise 4-12 ms ahead of it; candidates opened there (AAC: two whose onset picks found
// no change point, so neither impact nor tentative; Vorbis: one 4 ms before the 5th bounce), and
// the residual's novelty rose from them into the bounce without the dip that re-arms it: the
// bounce was never a candidate. In a transform codec's file the residual now re-arms a window
// after the last candidate began (CandidateTracker). Each copy: the WAV's eta-bar, and at most one
// impact more than the WAV (a codec may still make one sound of the room stand out).
TEST_F(CodecInput, CopiesOfTheSuitesReverbStrongDropKeepItsSequenceAndItsImpacts) {
  const fs::path wav = DetectorSuiteRecording("reverb_strong.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto impacts_of = [&](const fs::path& file) {
    const auto json = folder_.path() / (file.filename().string() + ".json");
    EXPECT_EQ(
        RunBouncecal("analyze '" + file.string() + "' --json '" + json.string() + "'").exit_status,
        0);
    return ReadJson(json)["impacts"].size();
  };
  const auto wav_impacts = impacts_of(wav);
  const auto reference = FirstSequence(wav, folder_.path());
  for (const auto& [name, options] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"reverb_strong.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}},
           {"reverb_strong.m4a", {"-c:a", "aac", "-b:a", "128k"}},
           {"reverb_strong.ogg", {"-c:a", "libvorbis", "-q:a", "4"}}}) {
    SCOPED_TRACE(name);
    const auto copy = Encode(wav, name, options);
    EXPECT_LE(impacts_of(copy), wav_impacts + 1);
    ExpectTheWavsEtaBar(reference, FirstSequence(copy, folder_.path()), 0.002);
  }
}

// Issue 30: noise_snr12 as Vorbis q4 (the WAV: 0.5507). The encoder's long block spread the 4th
// bounce's noise 15 ms ahead of it; a candidate opened there, and the residual, re-armed a window
// later (a transform codec's file: CandidateTracker), opened a second one whose pick, bounded by
// the first's onset, landed 30 us after it: the pair counted as a full rise and made a stray
// impact, with which the 5th bounce, heard only in the ringing, timed like chance (no sequence).
// A candidate re-armed that way whose pick lies on the bound found no sound of its own, and is
// none: the WAV's eta-bar.
TEST_F(CodecInput, AVorbisCopyOfTheSuitesNoisyDropMakesNoImpactOfAPreEchoTwice) {
  const fs::path wav = DetectorSuiteRecording("noise_snr12.wav");
  if (!fs::exists(wav)) GTEST_SKIP() << wav << " is absent (BOUNCECAL_SHARED_DIR)";
  const auto ogg = Encode(wav, "noise_snr12.ogg", {"-c:a", "libvorbis", "-q:a", "4"});
  ExpectTheWavsEtaBar(FirstSequence(wav, folder_.path()), FirstSequence(ogg, folder_.path()),
                      0.002);
}

}  // namespace
}  // namespace bouncecal::testing
