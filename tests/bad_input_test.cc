// The bad-input catalogue (issue 7): every hostile recording, material card or packing scene
// gives one line naming the file and the problem, the README's exit status (2: an input file is
// missing, unreadable or malformed, whichever field is wrong), and no output file. The bad files
// are written byte by byte here, so each case shows exactly what is wrong with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"
#include "lossy_encode.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

class BadInput : public ::testing::Test {
 public:
  fs::path Write(const std::string& name, const std::string& bytes) const {
    std::ofstream(folder_ / name, std::ios::binary) << bytes;
    return folder_ / name;
  }

  // Runs the command with --json (or -o) pointing into the scratch folder and checks the
  // contract: the status, one line, the input's path and the problem's words in it, no output.
  void ExpectRefused(const std::string& command, const fs::path& input, int status,
                     const std::string& problem, const std::string& output_flag = "--json") {
    const fs::path output = folder_ / "out.json";
    const auto result = RunBouncecal(command + " '" + input.string() + "' " + output_flag + " '" +
                                     output.string() + "'");
    SCOPED_TRACE(input.filename().string() + ": " + result.output);
    EXPECT_EQ(result.exit_status, status);
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1);
    EXPECT_NE(result.output.find(input.string()), std::string::npos);
    std::string lower = result.output;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    EXPECT_NE(lower.find(problem), std::string::npos) << "expected the words: " << problem;
    EXPECT_FALSE(fs::exists(output));
  }

  const ScratchFolder folder_;
};

void Append16(std::string& bytes, std::uint16_t value) {
  bytes.push_back(static_cast<char>(value & 0xff));
  bytes.push_back(static_cast<char>(value >> 8));
}

void Append32(std::string& bytes, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) bytes.push_back(static_cast<char>(value >> shift));
}

// A canonical 44-byte-header WAV; the data chunk's size field says `claimed_data_bytes`
// whatever `data` really holds, so headers can lie.
std::string Wav(std::uint16_t format_tag, int channels, int rate_hz, int bits,
                const std::string& data, std::uint32_t claimed_data_bytes) {
  std::string bytes = "RIFF";
  Append32(bytes, 36 + claimed_data_bytes);
  bytes += "WAVEfmt ";
  Append32(bytes, 16);
  Append16(bytes, format_tag);
  Append16(bytes, static_cast<std::uint16_t>(channels));
  Append32(bytes, static_cast<std::uint32_t>(rate_hz));
  // The byte rate in 64 bits: at an absurd rate (520 MHz) it overflows an int (UBSan found it);
  // the 32-bit field then wraps, as it would in a header that lies.
  Append32(bytes, static_cast<std::uint32_t>(static_cast<std::uint64_t>(rate_hz) * channels *
                                             static_cast<std::uint64_t>(bits) / 8));
  Append16(bytes, static_cast<std::uint16_t>(channels * bits / 8));
  Append16(bytes, static_cast<std::uint16_t>(bits));
  bytes += "data";
  Append32(bytes, claimed_data_bytes);
  return bytes + data;
}

constexpr std::uint16_t kPcm = 1;
constexpr std::uint16_t kIeeeFloat = 3;
constexpr std::uint16_t kMpegLayer3 = 0x55;

std::string Pcm16(int frames) {
  std::string data;
  for (int i = 0; i < frames; ++i) Append16(data, static_cast<std::uint16_t>(100 * (i % 7)));
  return data;
}

std::string Pcm16Wav(int frames, int rate_hz = 48000) {
  const std::string data = Pcm16(frames);
  return Wav(kPcm, 1, rate_hz, 16, data, static_cast<std::uint32_t>(data.size()));
}

std::string FloatWavWith(float bad_value) {
  std::vector<float> samples(4800, 0.001f);
  samples[2400] = bad_value;
  std::string data(reinterpret_cast<const char*>(samples.data()), samples.size() * sizeof(float));
  return Wav(kIeeeFloat, 1, 48000, 32, data, static_cast<std::uint32_t>(data.size()));
}

TEST_F(BadInput, UnreadableRecordingsAreInputErrorsWithoutOutput) {
  ExpectRefused("analyze", folder_ / "missing.wav", 2, "missing.wav");
  ExpectRefused("analyze", Write("empty.wav", ""), 2, "empty.wav");
  fs::create_directory(folder_ / "folder.wav");
  ExpectRefused("analyze", folder_ / "folder.wav", 2, "folder.wav");
  ExpectRefused("analyze", Write("text.wav", "time,height\n0,0.2\n"), 2, "text.wav");
  ExpectRefused("analyze", Write("header_only_half.wav", Pcm16Wav(1000).substr(0, 30)), 2,
                "header_only_half.wav");
  ExpectRefused("analyze", Write("codec.wav", Wav(kMpegLayer3, 1, 48000, 16, Pcm16(1000), 2000)), 2,
                "codec.wav");
}

// What libsndfile does not recognise goes to FFmpeg, which must refuse media that is not a
// recording as firmly, and must not follow a playlist or script to other files.
TEST_F(BadInput, MediaFilesThatAreNotRecordingsAreRefusedInOneLine) {
  std::string mp4 = std::string("\0\0\0\x18", 4) + "ftypM4A " + std::string(4, '\0') + "M4A mp42";
  for (int i = 0; i < 3000; ++i) mp4.push_back(static_cast<char>((i * 7919) % 251));
  ExpectRefused("analyze", Write("garbage.m4a", mp4), 2, "garbage.m4a");
  Write("drop.wav", Pcm16Wav(48000));
  ExpectRefused("analyze",
                Write("playlist.m3u8",
                      "#EXTM3U\n#EXT-X-TARGETDURATION:1\n#EXTINF:1,\ndrop.wav\n"
                      "#EXT-X-ENDLIST\n"),
                2, "not a readable audio file");
  ExpectRefused("analyze", Write("script.ffconcat", "ffconcat version 1.0\nfile 'drop.wav'\n"), 2,
                "not a readable audio file");
  // An ID3 tag or an MPEG frame header over garbage: libsndfile's mpg123 printed "Note: Trying
  // to resync..." lines of its own; FFmpeg alone reads what starts like MP3.
  std::string id3 = std::string("ID3\x04\0\0\0\0\0\x23", 10);
  std::string sync = "\xff\xfb\x90\x64";
  for (int i = 0; i < 3000; ++i) {
    id3.push_back(static_cast<char>((i * 7919) % 251));
    sync.push_back(static_cast<char>((i * 7919) % 251));
  }
  ExpectRefused("analyze", Write("garbage_id3.mp3", id3), 2, "garbage_id3.mp3");
  ExpectRefused("analyze", Write("garbage_sync.mp3", sync), 2, "garbage_sync.mp3");
  // An Ogg page header with nothing decodable behind it.
  ExpectRefused("analyze", Write("empty.ogg", std::string("OggS\0\x02", 6) + std::string(40, '\0')),
                2, "empty.ogg");
}

TEST_F(BadInput, TheRefusalOfAnUnreadableFileListsTheFormatsThatAreRead) {
  const auto text = Write("notes.wav", "drop 1: 0.20 m\n");
  ExpectRefused("analyze", text, 2, "not a readable audio file");
  const auto result = RunBouncecal("analyze '" + text.string() + "'");
  for (const std::string format : {"WAV", "FLAC", "OGG", "MP3", "M4A/AAC"}) {
    EXPECT_NE(result.output.find(format), std::string::npos) << format << ": " << result.output;
  }
}

// Phone formats go through FFmpeg (or, for MP3, libsndfile's mpg123): a copy cut short or
// damaged in transfer must be refused, never decoded around, since a frame dropped or concealed
// mid-stream moves every later onset. The files are encoded by the ffmpeg command from a
// 1 kHz tone, then cut in half or have 2000 bytes in the middle of their audio overwritten.
TEST_F(BadInput, TruncatedOrCorruptPhoneRecordingsAreRefusedAsDamaged) {
  if (!FfmpegAvailable()) GTEST_SKIP() << FfmpegMissingMessage();
  const auto wav = folder_ / "tone.wav";
  ASSERT_TRUE(RunFfmpeg({"-f", "lavfi", "-i", "sine=f=1000:d=3:r=48000"}, wav));
  struct Setting {
    std::string name;
    std::vector<std::string> options;
  };
  // An M4A with its index (moov) at the end, as ffmpeg writes it; one with the index first, as
  // phones write voice memos, whose cut copy keeps an index promising the lost audio; an MP3
  // with the LAME tag that states its length.
  const std::vector<Setting> settings = {
      {"moov_last.m4a", {"-c:a", "aac", "-b:a", "128k"}},
      {"moov_first.m4a", {"-c:a", "aac", "-b:a", "128k", "-movflags", "+faststart"}},
      {"lame.mp3", {"-c:a", "libmp3lame", "-b:a", "128k"}},
  };
  for (const auto& setting : settings) {
    const auto whole_path = folder_ / ("whole_" + setting.name);
    ASSERT_TRUE(EncodeWithFfmpeg(wav, whole_path, setting.options)) << setting.name;
    std::ifstream in(whole_path, std::ios::binary);
    const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(whole.size(), 20000u) << setting.name;
    ExpectRefused("analyze", Write("cut_" + setting.name, whole.substr(0, whole.size() / 2)), 2,
                  "cut_" + setting.name);
    std::string corrupt = whole;
    for (std::size_t i = 0; i < 2000; ++i) {
      corrupt[whole.size() / 2 + i] = static_cast<char>((i * 7919 + 13) % 251);
    }
    ExpectRefused("analyze", Write("corrupt_" + setting.name, corrupt), 2,
                  "corrupt_" + setting.name);
  }
}

TEST_F(BadInput, AVideoWithoutSoundIsRefusedForHavingNoAudioStream) {
  if (!FfmpegAvailable()) GTEST_SKIP() << FfmpegMissingMessage();
  const auto video = folder_ / "silent.mp4";
  ASSERT_TRUE(RunFfmpeg({"-f", "lavfi", "-i", "testsrc=d=1:s=64x48:r=10", "-c:v", "mpeg4"}, video));
  ExpectRefused("analyze", video, 2, "without an audio stream");
}

// Two microphones, or a drop and a commentary track: analysing the one FFmpeg ranks first would
// be a guess, so the user is asked to pick.
TEST_F(BadInput, AFileWithTwoAudioStreamsIsRefusedRatherThanGuessed) {
  if (!FfmpegAvailable()) GTEST_SKIP() << FfmpegMissingMessage();
  const auto two = folder_ / "two_microphones.m4a";
  ASSERT_TRUE(RunFfmpeg({"-f", "lavfi", "-i", "sine=f=1000:d=2:r=48000", "-f", "lavfi", "-i",
                         "sine=f=300:d=2:r=48000", "-map", "0:a", "-map", "1:a", "-c:a", "aac"},
                        two));
  ExpectRefused("analyze", two, 2, "2 audio streams");
}

TEST_F(BadInput, TruncatedOrLyingRecordingsAreRefusedAsTruncated) {
  const std::string whole = Pcm16Wav(48000);
  ExpectRefused("analyze", Write("cut_in_data.wav", whole.substr(0, whole.size() / 2)), 2,
                "truncated");
  // The header claims a million frames; the file holds a thousand.
  ExpectRefused("analyze", Write("claims_more.wav", Wav(kPcm, 1, 48000, 16, Pcm16(1000), 2000000)),
                2, "truncated");
}

TEST_F(BadInput, NonFiniteFloatSamplesAreRefusedWithTheirPosition) {
  ExpectRefused("analyze", Write("nan.wav", FloatWavWith(std::numeric_limits<float>::quiet_NaN())),
                2, "sample 2400");
  ExpectRefused("analyze", Write("inf.wav", FloatWavWith(std::numeric_limits<float>::infinity())),
                2, "sample 2400");
  ExpectRefused("analyze",
                Write("minus_inf.wav", FloatWavWith(-std::numeric_limits<float>::infinity())), 2,
                "infinite");
}

TEST_F(BadInput, RecordingsWithNoOrOneSampleAreTooShort) {
  ExpectRefused("analyze", Write("zero_samples.wav", Pcm16Wav(0)), 2, "zero_samples.wav");
  ExpectRefused("analyze", Write("one_sample.wav", Pcm16Wav(1)), 2, "1 sample");
}

TEST_F(BadInput, RatesBelow8kHzAreRefusedAndTheMinimumIsNamed) {
  ExpectRefused("analyze", Write("rate_4k.wav", Pcm16Wav(4000, 4000)), 2, "8000 hz");
}

// Fuzzing finding: a header claiming 520 MHz made the detector size its windows for that rate
// and allocate gigabytes before reading a sample.
TEST_F(BadInput, AbsurdSampleRatesAreRefusedBeforeAnythingIsAllocated) {
  ExpectRefused("analyze", Write("rate_520mhz.wav", Pcm16Wav(256, 520110080)), 2, "768000 hz");
}

// Cases that must work: a telephone-rate recording and a six-channel recorder.
audio::SynthesisOptions Drop(int rate_hz) {
  audio::SynthesisOptions options;
  options.sample_rate_hz = rate_hz;
  options.drop.drop_height_m = 0.2;
  for (auto& mode : options.modes) mode.decay_s *= 0.1;  // a damped plate, see analyze_cli_test
  options.noise = audio::NoiseOptions{};
  options.seed = 7;
  return options;
}

nlohmann::json AnalyzeToJson(const fs::path& input, const fs::path& json) {
  const auto result = RunBouncecal("analyze '" + input.string() + "' --json '" + json.string() +
                                   "' --drop-height-m 0.2");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  // fmt prints a NaN or infinity as "nan" or "inf"; the report must never show one.
  EXPECT_FALSE(std::regex_search(result.output, std::regex(R"(\b-?(nan|inf)\b)"))) << result.output;
  std::ifstream in(json);
  return nlohmann::json::parse(in);
}

TEST_F(BadInput, An8kHzRecordingIsAnalysed) {
  const auto synthesized = audio::SynthesizeBounces(Drop(8000));
  const auto path = folder_ / "drop_8k.wav";
  audio::WriteRecording(path, std::span<const audio::Recording>(synthesized.channels),
                        {audio::AudioContainer::kWav, audio::SampleEncoding::kPcm16});
  const auto json = AnalyzeToJson(path, folder_ / "drop_8k.json");
  const auto& file = json["recordings"][0];
  ASSERT_TRUE(file.contains("sample_rate_hz")) << file.dump();
  EXPECT_EQ(file["sample_rate_hz"], 8000);
  // At 8 kHz an onset is timed to a sample (125 us) at worst; the bounces are still found.
  EXPECT_GE(file["impacts"].size(), 5u) << file.dump();
}

TEST_F(BadInput, ASixChannelRecordingIsAnalysedOnItsLoudestChannel) {
  const auto synthesized = audio::SynthesizeBounces(Drop(48000));
  std::vector<audio::Recording> channels(6, synthesized.channels[0]);
  // Five dead inputs (digital silence: a noise floor of zero) and the microphone on input 4.
  for (int c = 0; c < 6; ++c) {
    if (c != 4) std::fill(channels[c].samples.begin(), channels[c].samples.end(), 0.0f);
  }
  const auto path = folder_ / "six_channels.wav";
  audio::WriteRecording(path, std::span<const audio::Recording>(channels),
                        {audio::AudioContainer::kWav, audio::SampleEncoding::kPcm16});
  const auto json = AnalyzeToJson(path, folder_ / "six.json");
  const auto& file = json["recordings"][0];
  EXPECT_EQ(file["channel"], 4) << file.dump();
  EXPECT_EQ(file["channel_count"], 6);
  EXPECT_GE(file["impacts"].size(), 5u);
}

// Material cards, read by `compare --material` (calibrate's reader) and `export --material`.
std::string Card(const std::string& law, const std::string& ball, const std::string& extra = "") {
  return R"({"format": "bouncecal-material/1", "contact_law": )" + law + R"(, "ball": )" + ball +
         extra + "}";
}

const std::string kLaw =
    R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}})";
const std::string kBall = R"({"diameter_m": 0.01, "density_kg_per_m3": 7800})";

// Both readers of a card: the problem, its exit status, the words the message must hold.
void ExpectCardRefused(BadInput& test, const fs::path& card, int status,
                       const std::string& problem) {
  test.ExpectRefused("compare " + SourceDir().string() +
                         "/samples/steel_ball_h0.2m.csv --drop-height-m 0.2 --material",
                     card, status, problem);
  test.ExpectRefused("export --engine lammps --material", card, status, problem, "-o");
}

TEST_F(BadInput, NonFiniteOptionValuesAreRefusedNamingTheOptionBeforeAnyWork) {
  // apps/finite_numbers.h: one check for every numeric option of every command, also for
  // options a command reads only in some modes (--trajectory-interval-s without --trajectory).
  const std::string sample = SourceDir().string() + "/samples/steel_ball_h0.2m.wav";
  const fs::path output = folder_ / "out.json";
  const struct {
    std::string arguments;
    std::string option;
  } cases[] = {
      {"calibrate '" + sample + "' --ball steel-10mm --drop-height-m nan", "--drop-height-m nan"},
      {"calibrate '" + sample + "' --ball steel-10mm --drop-height-m 0.2 --onset-uncertainty-s inf",
       "--onset-uncertainty-s inf"},
      {"simulate drop --trajectory-interval-s nan", "--trajectory-interval-s nan"},
      {"simulate drop --drop-height-m 1e999", "--drop-height-m 1e999"},
      {"analyze '" + sample + "' --band-low-hz -inf", "--band-low-hz -inf"},
  };
  for (const auto& c : cases) {
    const auto result = RunBouncecal(c.arguments + " --json '" + output.string() + "'");
    SCOPED_TRACE(c.arguments + ": " + result.output);
    EXPECT_EQ(result.exit_status, 3);
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1);
    EXPECT_NE(result.output.find(c.option), std::string::npos);
    EXPECT_NE(result.output.find("not a finite number"), std::string::npos);
    EXPECT_FALSE(fs::exists(output));
  }
}

TEST_F(BadInput, MaterialCardsThatAreNotCardsAreInputErrors) {
  ExpectCardRefused(*this, folder_ / "missing.json", 2, "missing.json");
  ExpectCardRefused(*this, Write("empty.json", ""), 2, "empty.json");
  ExpectCardRefused(*this, Write("not_json.json", "format: material\n"), 2, "not_json.json");
  ExpectCardRefused(*this, Write("array.json", "[1, 2]"), 2, "array.json");
  ExpectCardRefused(*this, Write("no_law.json", R"({"format": "bouncecal-material/1"})"), 2,
                    "contact_law");
}

TEST_F(BadInput, MaterialCardFieldsWithWrongTypesOrValuesNameTheKey) {
  ExpectCardRefused(*this, Write("string_diameter.json", Card(kLaw, R"({"diameter_m": "1 cm"})")),
                    2, "diameter_m");
  ExpectCardRefused(*this,
                    Write("negative_diameter.json",
                          Card(kLaw, R"({"diameter_m": -0.01, "density_kg_per_m3": 7800})")),
                    2, "diameter_m");
  // 1e999 overflows a double: the JSON parser refuses it (and the export reader used to let that
  // escape as an internal error, exit status 1).
  ExpectCardRefused(*this,
                    Write("infinite_density.json",
                          Card(kLaw, R"({"diameter_m": 0.01, "density_kg_per_m3": 1e999})")),
                    2, "1e999");
  ExpectCardRefused(*this, Write("ball_array.json", Card(kLaw, "[0.01]")), 2, "ball");
  ExpectCardRefused(*this, Write("bad_fit.json", Card(kLaw, kBall, R"(, "fit": {"drag": "yes"})")),
                    2, "drag");
}

TEST_F(BadInput, UnknownKeysInACardAreRejectedByName) {
  ExpectCardRefused(*this, Write("typo_top.json", Card(kLaw, kBall, R"(, "bal": {})")), 2,
                    "\"bal\"");
  ExpectCardRefused(
      *this,
      Write("typo_ball.json", Card(kLaw, R"({"diameter_m": 0.01, "densty_kg_per_m3": 7800})")), 2,
      "\"densty_kg_per_m3\"");
}

// The law inside a card is part of the file like any other field: an out-of-range, unknown or
// mistyped law parameter, or an unknown key in "contact_law", is a bad input file (status 2),
// and the message names the card and the parameter.
TEST_F(BadInput, BadLawParametersInACardAreInputErrorsLikeAnyOtherField) {
  const std::string negative =
      R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": -0.5}})";
  ExpectCardRefused(*this, Write("negative_gamma.json", Card(negative, kBall)), 2, "gamma_n");
  const std::string unknown =
      R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gama_n": 0.5}})";
  ExpectCardRefused(*this, Write("unknown_parameter.json", Card(unknown, kBall)), 2, "gama_n");
  const std::string typo_key =
      R"({"law": "walton-braun", "parmeters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}})";
  ExpectCardRefused(*this, Write("unknown_law_key.json", Card(typo_key, kBall)), 2,
                    "\"parmeters\"");
  const std::string string_gamma =
      R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": "0.5"}})";
  ExpectCardRefused(*this, Write("string_gamma.json", Card(string_gamma, kBall)), 2, "gamma_n");
  ExpectCardRefused(*this, Write("unknown_law.json", Card(R"({"law": "hooke"})", kBall)), 2,
                    "hooke");
}

// Options that cannot be honoured (issue 28): a law ranking with no degree of freedom, a contact
// duration that sets no stiffness. Usage errors (status 3) in one line with the numbers and what
// to do, and no output file.
TEST_F(BadInput, RankingsWithoutDataAndUnusableContactDurationsAreRefusedInOneLine) {
  const std::string csv = SourceDir().string() + "/samples/steel_ball_h0.2m.csv";
  const fs::path output = folder_ / "out.json";
  const auto expect = [&](const std::string& command, const std::string& words) {
    const auto result = RunBouncecal(command + " --json '" + output.string() + "'");
    SCOPED_TRACE(command + ": " + result.output);
    EXPECT_EQ(result.exit_status, 3);
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1);
    EXPECT_NE(result.output.find(words), std::string::npos) << "expected the words: " << words;
    EXPECT_FALSE(fs::exists(output));
  };
  expect("calibrate " + csv +
             " --ball steel-10mm --drop-height-m 0.2 --compare-laws --objective mean-energy-loss",
         "gives 1 datum(s) against 1 fitted parameter(s)");
  expect("calibrate " + csv + " --ball steel-10mm --drop-height-m 0.2 --contact-duration-s -1",
         "positive number of seconds");
  expect("calibrate " + csv + " --drop-height-m 0.2 --contact-duration-s 0.005",
         "--contact-duration-s needs the ball");
  expect("simulate drop --ball tennis --law hertz-viscoelastic --contact-duration-s 0.005",
         "give the law's effective_modulus_pa instead (--param)");
  expect("simulate drop --ball tennis --contact-duration-s 0.005 --param stiffness_n_per_m=1e5",
         "both set the stiffness");
}

// Scene files for `bouncecal pack`. Every problem of the scene file, or of the start-positions
// file it names, is a bad input file (status 2): one line naming the file (and for a scene the
// key's path), and neither the output folder nor the --json file appears.
nlohmann::json TinyScene() {
  return nlohmann::json::parse(R"({
    "format": "bouncecal-scene/1",
    "particles": {"count": 20, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.03, "z_min_m": 0.0, "z_max_m": 0.05}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5, "duration_s": 0.001,
    "measurement": {"band_m": [0.005, 0.02]}
  })");
}

class BadScene : public BadInput {
 public:
  fs::path WriteScene(const std::string& name, const nlohmann::json& scene) const {
    return Write(name, scene.dump(2));
  }

  // Runs `pack` on the scene and checks the contract; `named` is the file the message must name
  // (the scene itself unless the problem lies in a file the scene points to).
  void ExpectSceneRefused(const fs::path& scene, const std::string& problem,
                          const fs::path& named = {}) const {
    const fs::path out = folder_ / "pack_out";
    const fs::path json = folder_ / "pack.json";
    const auto result = RunBouncecal("pack '" + scene.string() + "' -o '" + out.string() +
                                     "' --json '" + json.string() + "'");
    SCOPED_TRACE(scene.filename().string() + ": " + result.output);
    EXPECT_EQ(result.exit_status, 2);
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1);
    EXPECT_NE(result.output.find((named.empty() ? scene : named).string()), std::string::npos);
    EXPECT_NE(result.output.find(problem), std::string::npos) << "expected the words: " << problem;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(json));
  }
};

TEST_F(BadScene, ScenesThatAreNotScenesAreInputErrors) {
  ExpectSceneRefused(folder_ / "missing.json", "cannot open");
  ExpectSceneRefused(Write("empty.json", ""), "not valid JSON");
  ExpectSceneRefused(Write("yaml.json", "format: bouncecal-scene/1\n"), "not valid JSON");
  ExpectSceneRefused(Write("array.json", "[1, 2]"), "top level: must be a JSON object");
  auto scene = TinyScene();
  scene["format"] = "bouncecal-scene/9";
  ExpectSceneRefused(WriteScene("future.json", scene), "bouncecal-scene/9");
}

TEST_F(BadScene, MissingFieldsAndWrongTypesNameTheKeyPath) {
  auto scene = TinyScene();
  scene["particles"].erase("count");
  ExpectSceneRefused(WriteScene("no_count.json", scene), "particles.count: is missing");
  scene = TinyScene();
  scene.erase("measurement");
  ExpectSceneRefused(WriteScene("no_measurement.json", scene), "measurement: is missing");
  scene = TinyScene();
  scene["time_step_s"] = "fast";
  ExpectSceneRefused(WriteScene("string_step.json", scene), "time_step_s: must be a number");
  scene = TinyScene();
  scene["particles"]["count"] = 20.5;
  ExpectSceneRefused(WriteScene("fractional_count.json", scene),
                     "particles.count: must be a whole number");
  scene = TinyScene();
  scene["container"] = "cylinder";
  ExpectSceneRefused(WriteScene("string_container.json", scene), "container: must be a JSON");
  scene = TinyScene();
  scene["measurement"]["band_m"] = {0.005, "high"};
  ExpectSceneRefused(WriteScene("string_band.json", scene), "measurement.band_m: must be an array");
  scene = TinyScene();
  scene["material"]["contact_law"]["parameters"] = {{"gamma_n", "0.5"}};
  ExpectSceneRefused(WriteScene("string_gamma.json", scene), "gamma_n");
}

TEST_F(BadScene, NegativeAndNonFiniteValuesAreRefusedWithTheValidRange) {
  auto scene = TinyScene();
  scene["container"]["radius_m"] = -0.03;
  ExpectSceneRefused(WriteScene("negative_radius.json", scene),
                     "container.radius_m: -0.03 is outside the valid range");
  scene = TinyScene();
  scene["particles"]["species"][0]["density_kg_per_m3"] = -7800;
  ExpectSceneRefused(WriteScene("negative_density.json", scene),
                     "particles.species[0].density_kg_per_m3");
  scene = TinyScene();
  scene["material"]["contact_law"]["parameters"] = {{"gamma_n", -0.5}};
  ExpectSceneRefused(WriteScene("negative_gamma.json", scene), "gamma_n");
  // JSON has no NaN or infinity; the nearest a file gets is a number that overflows a double,
  // which the parser refuses by its text.
  std::string text = TinyScene().dump();
  text.replace(text.find("\"duration_s\":0.001"), 18, "\"duration_s\":1e999");
  ExpectSceneRefused(Write("infinite_duration.json", text), "1e999");
}

TEST_F(BadScene, UnknownKeysAreRejectedWithTheirNameAndPath) {
  auto scene = TinyScene();
  scene["colour"] = "red";
  ExpectSceneRefused(WriteScene("top_key.json", scene), "unknown key 'colour'");
  scene = TinyScene();
  scene["material"]["frictoin"] = 0.3;
  ExpectSceneRefused(WriteScene("material_key.json", scene), "unknown key 'material.frictoin'");
  scene = TinyScene();
  scene["particles"]["species"][0]["colour"] = "grey";
  ExpectSceneRefused(WriteScene("species_key.json", scene),
                     "unknown key 'particles.species[0].colour'");
  scene = TinyScene();
  scene["insertion"]["region"]["radius"] = 0.03;
  ExpectSceneRefused(WriteScene("region_key.json", scene), "unknown key 'insertion.region.radius'");
  // The law object is read by the drop engine's parser; its unknown keys are bad files too.
  scene = TinyScene();
  scene["material"]["contact_law"]["parmeters"] = nlohmann::json::object();
  ExpectSceneRefused(WriteScene("law_key.json", scene), "\"parmeters\"");
  // A key is quoted back as it is written; a newline in it must not break the one line.
  scene = TinyScene();
  scene["particles"]["two\nlines"] = 1;
  ExpectSceneRefused(WriteScene("newline_key.json", scene), "two\\nlines");
}

TEST_F(BadScene, HugeParticleCountsAreRefusedWithTheMemoryTheyNeed) {
  auto scene = TinyScene();
  scene["particles"]["count"] = 2'000'000'000;
  // 2e9 spheres at ~1.4 kB each (EstimatedBytesPerParticle) is 2800 GB.
  ExpectSceneRefused(WriteScene("two_billion.json", scene), "would need about 2800.0 GB");
  scene["particles"]["count"] = 1e12;  // written as people write it: a float
  ExpectSceneRefused(WriteScene("trillion.json", scene), "GB of memory");
  scene["particles"]["count"] = std::numeric_limits<std::uint64_t>::max();
  ExpectSceneRefused(WriteScene("uint64_max.json", scene), "GB of memory");
}

TEST_F(BadScene, MissingOrGarbledStartPositionsFilesNameThatFile) {
  auto scene = TinyScene();
  scene["insertion"] = {{"type", "file"}, {"path", "start.csv"}};
  const fs::path scene_path = WriteScene("from_file.json", scene);
  const fs::path start = folder_ / "start.csv";
  ExpectSceneRefused(scene_path, "cannot open the particle file", start);
  Write("start.csv", "x_m,y_m,z_m,diameter_m\n0.0,0.0,0.01,0.01\n0.02,zero,0.01,0.01\n");
  ExpectSceneRefused(scene_path, "start.csv:3: 'zero' is not a finite number", start);
  Write("start.csv", "x_m,y_m,diameter_m\n0.0,0.0,0.01\n");
  ExpectSceneRefused(scene_path, "no 'z_m' column", start);
  Write("start.csv", "x_m,y_m,z_m,diameter_m\n0.0,0.0,0.01\n");
  ExpectSceneRefused(scene_path, "3 fields where the header has 4", start);
  Write("start.csv", "x_m,y_m,z_m,diameter_m,species\n0.0,0.0,0.01,0.01,1e30\n");
  ExpectSceneRefused(scene_path, "'1e30' is not a whole number", start);
  Write("start.csv", "x_m,y_m,z_m,diameter_m,species\n0.0,0.0,0.01,0.01,3\n");
  ExpectSceneRefused(scene_path, "names species 3", start);
  scene["insertion"]["path"] = "start.data";
  const fs::path lammps_scene = WriteScene("from_lammps.json", scene);
  Write("start.data", "LAMMPS data\n\n2 atoms\n\nAtoms # sphere\n\n1 1 0.01 7800 0 0 0.01\n");
  ExpectSceneRefused(lammps_scene, "holds 1 of the 2 atoms", folder_ / "start.data");
  // The header's count is judged by memory before any atom is read, as the scene's count is.
  Write("start.data", "LAMMPS data\n\n3000000000 atoms\n\nAtoms # sphere\n\n");
  ExpectSceneRefused(lammps_scene, "3000000000 particles would need about 4200.0 GB",
                     folder_ / "start.data");
}

// A start-positions file is read once, when the scene is loaded and checked; the run places the
// particles that were checked. (The run read it a second time: a file replaced in between ran
// unchecked particles, a pipe could not be read twice.) Here the file is garbled after loading:
// the run must not notice.
TEST_F(BadScene, StartPositionsFileIsReadOnceWhenTheSceneLoads) {
  auto json = TinyScene();
  json["particles"]["count"] = 2;
  json["insertion"] = {{"type", "file"}, {"path", "start.csv"}};
  Write("start.csv", "x_m,y_m,z_m,diameter_m\n0.0,0.0,0.01,0.01\n0.015,0.0,0.01,0.01\n");
  const dem::Scene scene = dem::LoadScene(WriteScene("from_file.json", json));
  Write("start.csv", "garbled after loading\n");
  dem::PackOptions options;
  options.duration_s = 0.0;
  const auto summary = dem::RunPacking(scene, options);
  ASSERT_EQ(summary.final_state.size(), 2u);
  EXPECT_EQ(summary.final_state.position_m[1][0], 0.015);
  EXPECT_EQ(summary.final_state.radius_m[0], 0.005);
}

TEST_F(BadScene, ANameThatIsNotAFolderNameIsRefused) {
  auto scene = TinyScene();
  scene["name"] = "../../elsewhere";
  ExpectSceneRefused(WriteScene("slash_name.json", scene), "name: must be");
  scene["name"] = "it's";
  ExpectSceneRefused(WriteScene("quote_name.json", scene), "name: must be");
}

}  // namespace
}  // namespace bouncecal::testing
