// Analysis speed (seconds of audio per CPU second) and peak memory of the impact detector on
// 48 kHz mono. The 10-minute file is generated here, streamed to disk in blocks, so the
// generator does not inflate the peak memory the file analysis reports.
//
//   build/bench/analyze_bench                       # both benchmarks
//   build/bench/analyze_bench --benchmark_filter=File
#include <benchmark/benchmark.h>
#include <sndfile.h>
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/detect_file.h"
#include "bouncecal/audio/impact_detector.h"

namespace {

constexpr int kRateHz = 48000;

// Noise at -60 dBFS plus a bouncing-ball-like impact (three decaying modes) every 0.25-0.5 s.
class Generator {
 public:
  explicit Generator(unsigned seed) : random_(seed) {}
  void Fill(std::vector<float>& block) {
    std::normal_distribution<double> noise(0.0, 1e-3);
    std::uniform_real_distribution<double> gap(0.25, 0.5);
    for (auto& x : block) {
      const double t = static_cast<double>(index_++) / kRateHz;
      if (t >= next_impact_s_) {
        last_impact_s_ = next_impact_s_;
        next_impact_s_ += gap(random_);
      }
      const double u = t - last_impact_s_;
      double value = noise(random_);
      if (last_impact_s_ >= 0 && u < 0.1) {
        value += 0.3 * std::exp(-u / 0.02) *
                 (std::sin(2 * std::numbers::pi * 1800 * u) +
                  0.6 * std::sin(2 * std::numbers::pi * 4300 * u) +
                  0.4 * std::sin(2 * std::numbers::pi * 9100 * u));
      }
      x = static_cast<float>(value);
    }
  }

 private:
  std::mt19937 random_;
  long long index_ = 0;
  double last_impact_s_ = -1;
  double next_impact_s_ = 0.3;
};

double PeakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// In memory: the detector alone on 60 s of audio.
void BM_DetectImpacts60s(benchmark::State& state) {
  bouncecal::audio::Recording recording;
  recording.sample_rate_hz = kRateHz;
  recording.samples.resize(60 * kRateHz);
  Generator(1).Fill(recording.samples);
  for (auto _ : state) {
    benchmark::DoNotOptimize(bouncecal::audio::DetectImpacts(recording));
  }
  state.counters["audio_s_per_cpu_s"] = benchmark::Counter(
      60.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectImpacts60s)->Unit(benchmark::kMillisecond);

// From a 10-minute 16-bit WAV: reading, detection and sequence finding, with peak memory.
void BM_AnalyzeFile10min(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / "bouncecal_bench_10min.wav";
  constexpr long long kFrames = 600LL * kRateHz;
  {
    SF_INFO info{};
    info.samplerate = kRateHz;
    info.channels = 1;
    info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
    SNDFILE* file = sf_open(path.c_str(), SFM_WRITE, &info);
    if (file == nullptr) {
      state.SkipWithError("cannot write the temporary WAV");
      return;
    }
    Generator generator(2);
    std::vector<float> block(1 << 16);
    for (long long done = 0; done < kFrames; done += static_cast<long long>(block.size())) {
      block.resize(static_cast<size_t>(std::min<long long>(1 << 16, kFrames - done)));
      generator.Fill(block);
      sf_writef_float(file, block.data(), static_cast<sf_count_t>(block.size()));
    }
    sf_close(file);
  }
  const double rss_before_mib = PeakRssMiB();
  size_t impacts = 0;
  for (auto _ : state) {
    const auto detection = bouncecal::audio::DetectImpactsInFile(path);
    const auto grouping = bouncecal::audio::FindBounceSequences(detection.detection.impacts);
    impacts = detection.detection.impacts.size();
    benchmark::DoNotOptimize(grouping);
  }
  state.counters["audio_s_per_cpu_s"] = benchmark::Counter(
      600.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["peak_rss_MiB"] = PeakRssMiB();
  state.counters["rss_before_MiB"] = rss_before_mib;
  state.counters["impacts"] = static_cast<double>(impacts);
  std::filesystem::remove(path);
}
BENCHMARK(BM_AnalyzeFile10min)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
