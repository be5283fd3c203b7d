// The sequence finder's chance test from both sides (docs/detector.md, "The chance test for
// impacts heard only in the ringing residual"):
//
// - false chains: Poisson random events, band-detected and residual-only at several rates, in
//   long files (10 min) and in short ones (a drop's few seconds), grouped by
//   audio::FindBounceSequences; every sequence with fewer than min_impacts band-detected
//   impacts that is not a short sequence was admitted by the chance test, and the test states
//   at most max_chance_alignment (1 %) such files; with --codec-frame-s, as events of a
//   transform codec's file with that frame (SequenceOptions::codec_frame_s); with
//   --tentative-hz R, tentative rises at R per s among them as well (a noisy or lossy file's),
//   which sequences and chains the chance test refused may adopt (ExtendSequencesWithTentative);
// - scattered drops: the chain-coverage bench's drops (calibrate_chain_coverage_bench: steel on
//   copper and on an anvil, e_k = e (1 + j z_k), synthesised with reverb and noise, written as
//   WAV, detected and grouped as `calibrate` does), and a lossy steel-on-lead drop (e = 0.5 from
//   0.30 m, whose 4th and 5th bounces sit in the first ones' ringing); how many form no
//   sequence of at least 4 impacts, and for those, what chain the test refused and why.
//
//   sequence_chance_bench [--files N (20)] [--short-files M (20000)] [--drops D (200)]
//                         [--skip-random] [--skip-drops] [--only DROP] [--jitter J] [--verbose]
//                         [--codec-frame-s F] [--tentative-hz R]
//
// It prints figures and asserts nothing.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/random_stream.h"

namespace {

namespace audio = bouncecal::audio;

constexpr double kGravity = 9.81;

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// Poisson events of both kinds over duration_s, levels uniform in dBFS, onset sigmas as the
// detector states them (a band onset ~20 us, a residual-only one a whole hop, 1.8 ms).
std::vector<audio::Impact> RandomEvents(double band_hz, double residual_hz, double duration_s,
                                        std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> level_dbfs(-40, -10);
  std::vector<audio::Impact> impacts;
  for (int kind = 0; kind < 2; ++kind) {
    const double rate_hz = kind == 0 ? band_hz : residual_hz;
    if (rate_hz <= 0) continue;
    std::exponential_distribution<double> gap_s(rate_hz);
    for (double t = gap_s(random); t < duration_s; t += gap_s(random)) {
      audio::Impact impact;
      impact.onset_s = t;
      impact.residual_only = kind == 1;
      impact.onset_uncertainty_s = kind == 1 ? 1.8e-3 : 20e-6;
      impact.peak_dbfs = level_dbfs(random);
      impacts.push_back(impact);
    }
  }
  std::sort(impacts.begin(), impacts.end(),
            [](const audio::Impact& a, const audio::Impact& b) { return a.onset_s < b.onset_s; });
  return impacts;
}

// Tentative rises at rate_hz over duration_s (sigma a hop, as the detector states them).
std::vector<audio::Impact> RandomTentative(double rate_hz, double duration_s, std::uint64_t seed) {
  std::vector<audio::Impact> tentative;
  if (rate_hz <= 0) return tentative;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> level_dbfs(-40, -10);
  std::exponential_distribution<double> gap_s(rate_hz);
  for (double t = gap_s(random); t < duration_s; t += gap_s(random)) {
    audio::Impact impact;
    impact.onset_s = t;
    impact.residual_only = true;
    impact.onset_uncertainty_s = 1.8e-3;
    impact.peak_dbfs = level_dbfs(random);
    tentative.push_back(impact);
  }
  return tentative;
}

// Chains the chance test admitted: sequences with fewer than min_impacts band-detected impacts,
// after the tentative rises were adopted where they continue a chain. `options` carries the
// codec's frame where the events stand for a lossy file's.
int AdmittedChains(const std::vector<audio::Impact>& detected,
                   const std::vector<audio::Impact>& tentative,
                   const audio::SequenceOptions& options, bool verbose) {
  const auto impacts = tentative.empty() || detected.empty()
                           ? detected
                           : audio::ExtendSequencesWithTentative(detected, tentative, options);
  int admitted = 0;
  for (const auto& sequence : audio::FindBounceSequences(impacts, options).sequences) {
    int band = 0;
    for (int i : sequence.impact_indices) {
      band += impacts[static_cast<std::size_t>(i)].residual_only ? 0 : 1;
    }
    if (sequence.short_sequence || band >= options.min_impacts) continue;
    ++admitted;
    if (!verbose) continue;
    std::printf("  admitted (chance %.3g):", sequence.chance_alignment);
    for (int i : sequence.impact_indices) {
      const auto& impact = impacts[static_cast<std::size_t>(i)];
      std::printf(" %.4f%s", impact.onset_s, impact.residual_only ? "w" : "b");
    }
    std::printf("\n");
  }
  return admitted;
}

void RandomEventsTable(int long_files, int short_files, const audio::SequenceOptions& options,
                       double tentative_hz, bool verbose) {
  struct Mix {
    double band_hz, residual_hz;
  };
  const Mix all[] = {{1, 4}, {4, 16}, {10, 40}, {0.5, 4.5}, {2.5, 2.5}, {3, 1}, {5, 5}};
  std::vector<Mix> mixes(std::begin(all), std::end(all));
  if (const char* only = std::getenv("CHANCE_BENCH_MIX")) {
    mixes = {{std::atof(only), std::atof(std::strchr(only, '/') + 1)}};
  }
  std::printf(
      "## False chains on random events\n\n"
      "| events per s (band / residual-only) | files | minutes each | chains admitted | files "
      "with one (stated <= 1 %%) | CPU s |\n| --- | --- | --- | --- | --- | --- |\n");
  for (const auto& mix : mixes) {
    for (const double minutes : {10.0, 3.0 / 60.0}) {
      const int files = minutes > 1 ? long_files : short_files;
      if (files <= 0) continue;
      int admitted = 0, with_one = 0;
      const double cpu = CpuSeconds();
      for (int f = 0; f < files; ++f) {
        const auto seed = static_cast<std::uint64_t>(9000 + f) * 7919 +
                          static_cast<std::uint64_t>(mix.band_hz * 100 + mix.residual_hz);
        const auto impacts = RandomEvents(mix.band_hz, mix.residual_hz, 60 * minutes, seed);
        const auto tentative = RandomTentative(tentative_hz, 60 * minutes, seed + 1);
        const int chains = AdmittedChains(impacts, tentative, options, verbose);
        admitted += chains;
        with_one += chains > 0 ? 1 : 0;
      }
      std::printf("| %.1f / %.1f | %d | %.2f | %d | %d (%.2f %%) | %.1f |\n", mix.band_hz,
                  mix.residual_hz, files, minutes, admitted, with_one, 100.0 * with_one / files,
                  CpuSeconds() - cpu);
      std::fflush(stdout);
    }
  }
}

struct DropKind {
  const char* name;
  double restitution;
  double drop_height_m;
};

// As calibrate_chain_coverage_bench's RecordDrop: ballistic flights down to 4 ms, e_k = e (1 +
// j z_k), the synthesiser's default plate with reverb and noise, 48 kHz PCM16.
audio::BounceAnalysis RecordDrop(const DropKind& kind, double jitter, std::uint64_t seed,
                                 std::uint64_t recording, std::vector<double>* truth) {
  bouncecal::RandomStream draws(seed, recording, 7);
  audio::SynthesisOptions synthesis;
  double onset = 0.3 + std::sqrt(2 * kind.drop_height_m / kGravity);
  double speed = std::sqrt(2 * kGravity * kind.drop_height_m);
  for (int k = 0; k < 60; ++k) {
    synthesis.impacts.push_back({onset, speed, 0});
    truth->push_back(onset);
    const double e = std::min(kind.restitution * (1 + jitter * draws.Gaussian()), 0.999);
    speed *= e;
    const double flight = 2 * speed / kGravity;
    if (flight < 0.004) break;
    onset += flight;
  }
  synthesis.reverb = audio::ReverbOptions{};
  synthesis.noise = audio::NoiseOptions{};
  synthesis.seed = seed * 16 + recording;
  const auto rendered = audio::SynthesizeBounces(synthesis);
  // The process id keeps two runs of the bench apart: with the seed and recording alone, the
  // second run's files were the first's, and one removed the other's before it was analysed.
  const auto path = std::filesystem::temp_directory_path() /
                    ("bouncecal_chance_" + std::to_string(::getpid()) + "_" + std::to_string(seed) +
                     "_" + std::to_string(recording) + ".wav");
  audio::WriteRecording(path, rendered.channels);
  audio::BounceAnalysis analysis = audio::AnalyzeBounces(path);
  std::filesystem::remove(path);
  return analysis;
}

bool HasSequence(const audio::BounceAnalysis& analysis) {
  for (const auto& sequence : analysis.grouping.sequences) {
    if (sequence.impact_indices.size() >= 4) return true;
  }
  return false;
}

// What the test refused: the chain that forms when the chance test lets everything through.
void Explain(const audio::BounceAnalysis& analysis, const std::vector<double>& truth) {
  auto impacts = analysis.detection.detection;
  audio::SequenceOptions anything;
  anything.max_chance_alignment = 1;
  const auto grouping = audio::GroupBounces(impacts, anything);
  for (const auto& impact : impacts.impacts) {
    double nearest = 1e9;
    for (double t : truth) nearest = std::min(nearest, std::fabs(t - impact.onset_s));
    std::printf("    %9.5f s %s %6.1f dBFS sigma %7.1f us, %6.2f ms from a bounce\n",
                impact.onset_s, impact.residual_only ? "residual" : "band    ", impact.peak_dbfs,
                impact.onset_uncertainty_s * 1e6, nearest * 1e3);
  }
  for (const auto& sequence : grouping.sequences) {
    std::printf("    chain of %zu (chance %.3g):", sequence.impact_indices.size(),
                sequence.chance_alignment);
    for (int i : sequence.impact_indices) std::printf(" %d", i);
    std::printf("\n");
  }
}

void DropsTable(int drops, bool verbose, const std::string& only, double only_jitter) {
  const DropKind kinds[] = {{"steel on copper", 0.65, 0.20},
                            {"steel on anvil", 0.80, 0.35},
                            {"steel on lead", 0.5, 0.30}};
  std::printf(
      "\n## Scattered drops: recordings with no sequence of >= 4 impacts\n\n"
      "| drop | jitter of e | recordings | no sequence | of them refused by the chance test | CPU "
      "s |\n| --- | --- | --- | --- | --- | --- |\n");
  for (const auto& kind : kinds) {
    if (std::string(kind.name).find(only) == std::string::npos) continue;
    for (const double jitter : {0.0, 0.03, 0.05, 0.10}) {
      if (only_jitter >= 0 && std::fabs(jitter - only_jitter) > 1e-9) continue;
      int none = 0, refused = 0;
      const double cpu = CpuSeconds();
      for (int d = 0; d < drops; ++d) {
        std::vector<double> truth;
        const auto analysis = RecordDrop(kind, jitter, 5000 + static_cast<std::uint64_t>(d / 5),
                                         static_cast<std::uint64_t>(d % 5), &truth);
        if (HasSequence(analysis)) continue;
        ++none;
        auto detection = analysis.detection.detection;
        audio::SequenceOptions anything;
        anything.max_chance_alignment = 1;
        const auto grouping = audio::GroupBounces(detection, anything);
        for (const auto& sequence : grouping.sequences) {
          if (sequence.impact_indices.size() >= 4) {
            ++refused;
            break;
          }
        }
        if (verbose) {
          std::printf("  %s j %.2f drop %d:\n", kind.name, jitter, d);
          Explain(analysis, truth);
        }
      }
      std::printf("| %s | %.0f %% | %d | %d | %d | %.1f |\n", kind.name, 100 * jitter, drops, none,
                  refused, CpuSeconds() - cpu);
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int files = 20, short_files = 20000, drops = 200;
  std::string only;
  double only_jitter = -1;
  bool random = true, scattered = true, verbose = false;
  audio::SequenceOptions options;
  double tentative_hz = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto next = [&]() { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
    if (arg == "--files") {
      files = next();
    } else if (arg == "--short-files") {
      short_files = next();
    } else if (arg == "--drops") {
      drops = next();
    } else if (arg == "--skip-random") {
      random = false;
    } else if (arg == "--skip-drops") {
      scattered = false;
    } else if (arg == "--only" && i + 1 < argc) {
      only = argv[++i];
    } else if (arg == "--jitter" && i + 1 < argc) {
      only_jitter = std::atof(argv[++i]);
    } else if (arg == "--verbose") {
      verbose = true;
    } else if (arg == "--codec-frame-s" && i + 1 < argc) {
      options.codec_frame_s = std::atof(argv[++i]);
    } else if (arg == "--tentative-hz" && i + 1 < argc) {
      tentative_hz = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: sequence_chance_bench [--files N] [--short-files M] [--drops D] "
                   "[--skip-random] [--skip-drops] [--only DROP] [--jitter J] [--verbose] "
                   "[--codec-frame-s F] [--tentative-hz R]\n");
      return 2;
    }
  }
  if (random) RandomEventsTable(files, short_files, options, tentative_hz, verbose);
  if (scattered) DropsTable(drops, verbose, only, only_jitter);
  return 0;
}
