// How much a lossy codec moves the onsets the detector finds: synthetic drops with exact ground
// truth are written as 16-bit WAV, encoded with Debian's encoders (the `ffmpeg` command: FFmpeg's
// AAC, LAME, libvorbis, libopus) at phone and export bit rates, decoded by the loader
// (load_recording.h) and analysed like the WAV. Per encoder setting and sample rate it prints
// the onset shift against the WAV's onsets (each drop's median shift removed: a constant offset
// cancels in every interval), the interval and eta-bar errors against the truth, and the sigma
// that covers 95 % of the shifts at 1.96 sigma: the codec timing uncertainty
// (audio/src/detector/codec_timing.cc holds the table derived from it, docs/codecs.md quotes it).
// It prints figures and asserts nothing.
//
//   build/bench/codec_timing_bench                      # every setting, 3 rates, 8 seeds
//   build/bench/codec_timing_bench --seeds 4 --only Opus --rate 48000
//
// Columns after sigma_us: the median stated onset sigma (detector, response timing and the
// codec table together) and the share of onsets whose error against the truth, less the drop's
// median error, lies within 1.96 stated sigmas; `own` counts the onsets stated with the response
// alignment's sigma instead of the codec table's.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/detect_file.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/load_recording.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "lossy_encode.h"

namespace {

namespace audio = bouncecal::audio;
namespace fs = std::filesystem;
using bouncecal::testing::LossyEncoding;

// Two scenes a phone records: a steel ball on a damped steel plate (modes ringing tens of ms) and
// a ping-pong ball on a counter (dense modes ringing over the next bounce, 9 ms echo). Drop
// height, restitution and loudness vary with the seed, 30 dB SNR referred to the weakest impact.
audio::SynthesisOptions Scene(const std::string& scene, int seed, int rate_hz) {
  audio::SynthesisOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  options.sample_rate_hz = rate_hz;
  const double u = std::fmod(0.6180339887 * seed, 1.0);
  const double w = std::fmod(0.7548776662 * seed, 1.0);
  options.peak_amplitude = 0.2 + 0.5 * std::fmod(0.5698402910 * seed, 1.0);
  options.drop.min_flight_s = 0.03;
  audio::NoiseOptions noise;
  noise.snr_db = 30;
  noise.reference = audio::SnrReference::kWeakestImpact;
  options.noise = noise;
  if (scene == "steel") {
    options.drop.drop_height_m = 0.15 + 0.35 * u;
    options.drop.restitution.constant = 0.55 + 0.35 * w;
    for (auto& mode : options.modes) mode.decay_s *= 0.1;
  } else {
    options.modes = audio::CounterTopModes();
    options.contact_duration_s = 50e-6;
    options.drop.drop_height_m = 0.2 + 0.2 * u;
    options.drop.restitution.constant = 0.85 + 0.1 * w;
    options.drop.max_impacts_per_drop = 25;
    audio::ReverbOptions reverb;
    reverb.rt60_s = 0.2;
    reverb.echoes = {{0.009, -12.0}};
    options.reverb = reverb;
  }
  return options;
}

struct Detected {
  std::vector<std::optional<double>> onsets;  // per true impact: the matched onset, if any
  std::vector<std::optional<double>> sigmas;  // and its stated uncertainty
  int extra = 0;
  bool sequence = false;
  std::optional<double> bit_rate_bps;
  int sample_rate_hz = 0;
  double table_sigma_s = 0;  // the codec table's share of every stated sigma
  int replaced = 0;          // onsets the response timing replaced (response_timing.h)
  int own_sigma = 0;         // onsets stated with the alignment's own sigma, without the table's
};

constexpr double kMatchS = 5e-3;

Detected Analyse(const fs::path& path, const std::vector<double>& truth) {
  // The file path analyze takes: for a lossy file or a low rate the response timing stage and
  // the codec's tabulated error are in the onsets and their uncertainties.
  auto file = audio::DetectImpactsInFile(path);
  auto& detection = file.detection;
  const auto grouping = audio::GroupBounces(detection);
  Detected result;
  result.bit_rate_bps = file.info.bit_rate_bps;
  result.sample_rate_hz = file.info.sample_rate_hz;
  result.sequence = !grouping.sequences.empty();
  if (file.codec_timing) result.table_sigma_s = file.codec_timing->onset_uncertainty_s;
  if (file.response_timing) {
    result.replaced = file.response_timing->replaced;
    result.own_sigma = file.response_timing->own_sigma;
  }
  const auto& impacts = detection.impacts;
  std::vector<bool> used(impacts.size(), false);
  for (double t : truth) {
    int best = -1;
    for (std::size_t i = 0; i < impacts.size(); ++i) {
      const double error = std::fabs(impacts[i].onset_s - t);
      if (!used[i] && error < kMatchS &&
          (best < 0 || error < std::fabs(impacts[static_cast<std::size_t>(best)].onset_s - t))) {
        best = static_cast<int>(i);
      }
    }
    if (best >= 0) {
      used[static_cast<std::size_t>(best)] = true;
      result.onsets.push_back(impacts[static_cast<std::size_t>(best)].onset_s);
      result.sigmas.push_back(impacts[static_cast<std::size_t>(best)].onset_uncertainty_s);
    } else {
      result.onsets.push_back(std::nullopt);
      result.sigmas.push_back(std::nullopt);
    }
  }
  for (bool u : used) result.extra += u ? 0 : 1;
  return result;
}

// Mean of 1 - e_k^2 over the first three ratios (no drop height): five onsets.
std::optional<double> EtaBar(const std::vector<std::optional<double>>& onsets) {
  if (onsets.size() < 5) return std::nullopt;
  for (int k = 0; k < 5; ++k) {
    if (!onsets[static_cast<std::size_t>(k)]) return std::nullopt;
  }
  double sum = 0;
  for (int k = 1; k <= 3; ++k) {
    const auto at = [&](int i) { return *onsets[static_cast<std::size_t>(i)]; };
    const double e = (at(k + 1) - at(k)) / (at(k) - at(k - 1));
    sum += 1 - e * e;
  }
  return sum / 3;
}

struct Tally {
  int drops = 0;
  int sequences = 0;
  int truth = 0;
  int found = 0;
  int extra = 0;
  std::vector<double> shifts_s;           // codec - WAV onset, signed
  std::vector<double> centred_shifts_s;   // less each drop's median shift
  std::vector<double> interval_errors_s;  // |codec interval - true interval|
  std::vector<double> eta_vs_wav;         // |eta-bar codec - eta-bar WAV|
  std::vector<double> eta_vs_truth;       // |eta-bar codec - exact eta-bar|
  std::vector<double> bit_rates_bps;
  std::vector<double> stated_s;  // stated onset sigma of every found impact
  std::vector<double> errors_s;  // |onset - truth| less the drop's median error
  std::vector<double> own_s;     // stated sigma without the codec table's share
  std::vector<bool> widened;     // the table's share is in it (below the table: the alignment's)
  int replaced = 0;
  int own_sigma = 0;
  int covered = 0;  // |error less the drop's median error| <= 1.96 stated sigma
  int judged = 0;
  int decoded_rate_hz = 0;
};

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()))];
}

std::vector<double> Abs(std::vector<double> values) {
  for (double& v : values) v = std::fabs(v);
  return values;
}

void Score(const Detected& codec, const Detected& wav, const std::vector<double>& truth,
           Tally& tally) {
  ++tally.drops;
  tally.replaced += codec.replaced;
  tally.own_sigma += codec.own_sigma;
  tally.sequences += codec.sequence ? 1 : 0;
  tally.truth += static_cast<int>(truth.size());
  tally.extra += codec.extra;
  tally.decoded_rate_hz = codec.sample_rate_hz;
  if (codec.bit_rate_bps) tally.bit_rates_bps.push_back(*codec.bit_rate_bps);
  std::vector<double> shifts;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (codec.onsets[k]) ++tally.found;
    if (codec.onsets[k] && wav.onsets[k]) shifts.push_back(*codec.onsets[k] - *wav.onsets[k]);
    if (k > 0 && codec.onsets[k] && codec.onsets[k - 1]) {
      tally.interval_errors_s.push_back(
          std::fabs(*codec.onsets[k] - *codec.onsets[k - 1] - (truth[k] - truth[k - 1])));
    }
  }
  // Coverage against the truth (each drop's median error removed: it cancels in intervals).
  std::vector<double> errors;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (codec.onsets[k]) errors.push_back(*codec.onsets[k] - truth[k]);
  }
  if (!errors.empty()) {
    const double median = Quantile(errors, 0.5);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      if (!codec.onsets[k]) continue;
      const double sigma = *codec.sigmas[k];
      tally.stated_s.push_back(sigma);
      tally.errors_s.push_back(std::fabs(*codec.onsets[k] - truth[k] - median));
      const bool widened = sigma >= codec.table_sigma_s;
      tally.widened.push_back(widened);
      tally.own_s.push_back(
          widened ? std::sqrt(sigma * sigma - codec.table_sigma_s * codec.table_sigma_s) : sigma);
      ++tally.judged;
      if (std::fabs(*codec.onsets[k] - truth[k] - median) <= 1.96 * sigma) ++tally.covered;
    }
  }
  if (!shifts.empty()) {
    const double median = Quantile(shifts, 0.5);
    for (double s : shifts) {
      tally.shifts_s.push_back(s);
      tally.centred_shifts_s.push_back(s - median);
    }
  }
  std::vector<std::optional<double>> exact(truth.begin(), truth.end());
  const auto eta = EtaBar(codec.onsets);
  const auto eta_wav = EtaBar(wav.onsets);
  const auto eta_exact = EtaBar(exact);
  if (eta && eta_wav) tally.eta_vs_wav.push_back(std::fabs(*eta - *eta_wav));
  if (eta && eta_exact) tally.eta_vs_truth.push_back(std::fabs(*eta - *eta_exact));
}

// The smallest codec table sigma with which 95 % of the errors against the truth lie within
// 1.96 stated sigmas (each onset's own sigma and the table's in quadrature; an onset stated
// below the table's sigma was timed by the response alignment alone and keeps its sigma).
double NeededTableSigma(const Tally& t) {
  const auto covered = [&](double table) {
    std::size_t within = 0;
    for (std::size_t i = 0; i < t.errors_s.size(); ++i) {
      const double sigma = t.widened[i] ? std::hypot(t.own_s[i], table) : t.own_s[i];
      within += t.errors_s[i] <= 1.96 * sigma ? 1 : 0;
    }
    return within >= 0.95 * static_cast<double>(t.errors_s.size());
  };
  double lo = 0;
  double hi = 5e-3;
  if (covered(lo)) return 0;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (covered(mid) ? hi : lo) = mid;
  }
  return hi;
}

void PrintRow(const std::string& label, int rate_hz, const Tally& t, bool reference) {
  const auto abs_centred = Abs(t.centred_shifts_s);
  std::printf("%-10s %6d %6d %5.0f %2d/%-2d %4d/%-4d %5d", label.c_str(), rate_hz,
              t.decoded_rate_hz,
              t.bit_rates_bps.empty() ? 0.0 : Quantile(t.bit_rates_bps, 0.5) / 1e3, t.sequences,
              t.drops, t.found, t.truth, t.extra);
  if (reference) {
    std::printf(" %8s %8s %8s %8s", "-", "-", "-", "-");
  } else {
    std::printf(" %8.1f %8.1f %8.1f %8.1f", Quantile(t.shifts_s, 0.5) * 1e6,
                Quantile(abs_centred, 0.5) * 1e6, Quantile(abs_centred, 0.95) * 1e6,
                abs_centred.empty()
                    ? 0.0
                    : *std::max_element(abs_centred.begin(), abs_centred.end()) * 1e6);
  }
  std::printf(" %8.1f %8.1f %8.4f %8.4f", Quantile(t.interval_errors_s, 0.5) * 1e6,
              Quantile(t.interval_errors_s, 0.95) * 1e6,
              reference ? 0.0 : Quantile(t.eta_vs_wav, 0.95), Quantile(t.eta_vs_truth, 0.95));
  if (reference) {
    std::printf(" %8s", "-");
  } else {
    std::printf(" %8.1f", Quantile(abs_centred, 0.95) / 1.96 * 1e6);
  }
  std::printf(" %8.1f %5.1f%% %8.1f %8.1f %5d %5d\n", Quantile(t.stated_s, 0.5) * 1e6,
              t.judged > 0 ? 100.0 * t.covered / t.judged : 0.0, Quantile(t.errors_s, 0.95) * 1e6,
              NeededTableSigma(t) * 1e6, t.replaced, t.own_sigma);
}

// --verbose: the onsets of a drop whose error against the truth (less the drop's median) exceeds
// 150 us, with their stated sigmas, to see what the codec did to them.
void PrintOutliers(const std::string& label, const std::string& scene, int seed, int rate,
                   const Detected& codec, const Detected& wav, const std::vector<double>& truth) {
  std::vector<double> errors;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (codec.onsets[k]) errors.push_back(*codec.onsets[k] - truth[k]);
  }
  if (errors.empty()) return;
  const double median = Quantile(errors, 0.5);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (!codec.onsets[k]) continue;
    const double error = *codec.onsets[k] - truth[k] - median;
    if (std::fabs(error) <= 150e-6) continue;
    std::printf(
        "  %s %d Hz %s seed %d impact %zu at %.4f s: error %+.0f us (WAV %+.0f), stated "
        "%.0f us\n",
        label.c_str(), rate, scene.c_str(), seed, k, truth[k], error * 1e6,
        wav.onsets[k] ? (*wav.onsets[k] - truth[k]) * 1e6 : 0.0, *codec.sigmas[k] * 1e6);
  }
}

// --only takes comma-separated substrings of the labels ("AAC 128k,Opus 64k").
bool Selected(const std::string& label, const std::string& only) {
  if (only.empty()) return true;
  std::size_t begin = 0;
  while (begin <= only.size()) {
    const std::size_t end = std::min(only.find(',', begin), only.size());
    if (end > begin && label.find(only.substr(begin, end - begin)) != std::string::npos) {
      return true;
    }
    begin = end + 1;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 8;
  std::string only;
  std::vector<int> rates = {48000, 44100, 16000};
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--verbose")) {
      verbose = true;
    } else if (!std::strcmp(argv[i], "--rate") && i + 1 < argc) {
      rates = {std::atoi(argv[++i])};
    } else {
      std::fprintf(stderr, "usage: %s [--seeds N] [--only SUBSTRING] [--rate HZ] [--verbose]\n",
                   argv[0]);
      return 2;
    }
  }
  if (!bouncecal::testing::FfmpegAvailable()) {
    std::fprintf(stderr, "codec_timing_bench: %s\n",
                 bouncecal::testing::FfmpegMissingMessage().c_str());
    return 1;
  }
  const fs::path folder =
      fs::temp_directory_path() / ("bouncecal_codec_bench_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  const std::vector<std::string> scenes = {"steel", "pingpong"};
  const auto encodings = bouncecal::testing::CommonLossyEncodings();
  std::map<std::pair<std::string, int>, Tally> tallies;  // (label, rate)
  std::map<int, Tally> wav_tallies;
  for (int rate : rates) {
    for (const auto& scene : scenes) {
      for (int seed = 1; seed <= seeds; ++seed) {
        const auto synthesized = audio::SynthesizeBounces(Scene(scene, seed, rate));
        const auto truth = synthesized.BallImpactOnsetsS();
        const fs::path wav_path = folder / "drop.wav";
        audio::WriteRecording(wav_path, synthesized.channels);
        const auto wav = Analyse(wav_path, truth);
        Score(wav, wav, truth, wav_tallies[rate]);
        for (const auto& encoding : encodings) {
          if (!Selected(encoding.label, only)) continue;
          const fs::path encoded = folder / ("encoded." + encoding.extension);
          fs::remove(encoded);
          if (!bouncecal::testing::EncodeWithFfmpeg(wav_path, encoded, encoding.ffmpeg_options)) {
            continue;  // a bit rate the rate does not allow (MP3 192k at 16 kHz)
          }
          const auto codec = Analyse(encoded, truth);
          Score(codec, wav, truth, tallies[{encoding.label, rate}]);
          if (verbose) PrintOutliers(encoding.label, scene, seed, rate, codec, wav, truth);
        }
      }
    }
  }
  fs::remove_all(folder);
  std::printf("%d seeds x %zu scenes per row; shifts are codec onset - WAV onset\n", seeds,
              scenes.size());
  std::printf(
      "%-10s %6s %6s %5s %5s %9s %5s %8s %8s %8s %8s %8s %8s %8s %8s %8s %8s %6s %8s %8s %5s %5s\n",
      "codec", "rate", "dec_hz", "kbps", "seq", "found", "extra", "bias_us", "c50_us", "c95_us",
      "cmax_us", "int50_us", "int95_us", "deta_wav", "deta_tru", "sigma_us", "stat50us", "cover",
      "e95_us", "need_us", "repl", "own");
  for (int rate : rates) PrintRow("WAV", rate, wav_tallies[rate], true);
  for (const auto& encoding : encodings) {
    for (int rate : rates) {
      if (!Selected(encoding.label, only)) continue;
      const auto found = tallies.find({encoding.label, rate});
      if (found != tallies.end()) PrintRow(encoding.label, rate, found->second, false);
    }
  }
  return 0;
}
