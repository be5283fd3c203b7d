// Analysis speed (seconds of audio per CPU second) and peak memory of the impact detector on
// 48 kHz mono. The 10-minute file is generated here, streamed to disk in blocks, and analysed
// by a fresh copy of this program (--analyze-file PATH), whose CPU time comes from wait4() and
// whose peak resident memory it reports itself (VmHWM): neither the generator nor the
// in-memory benchmark can inflate them. A copy that does nothing gives the baseline memory.
//
//   build/bench/analyze_bench                       # both benchmarks
//   build/bench/analyze_bench --benchmark_filter=File
#include <benchmark/benchmark.h>
#include <sndfile.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <optional>
#include <random>
#include <string>
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

struct ChildUsage {
  double cpu_s = 0;
  double peak_rss_mib = 0;
};

double Seconds(const timeval& t) {
  return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
}

// Peak resident set of this process image in MiB: VmHWM of /proc/self/status. Not
// getrusage's ru_maxrss, which Linux carries across execve() and so would report the parent's
// peak in a freshly started child.
double PeakRssMiB() {
  std::FILE* status = std::fopen("/proc/self/status", "r");
  if (status == nullptr) return -1;
  char line[256];
  double kib = -1;
  while (std::fgets(line, sizeof line, status) != nullptr) {
    if (std::sscanf(line, "VmHWM: %lf kB", &kib) == 1) break;
  }
  std::fclose(status);
  return kib / 1024.0;
}

// Runs this program again with the given arguments plus "--report FILE" and returns the
// child's CPU time (user + system, from wait4) and the peak resident set it wrote to FILE;
// nothing on failure.
std::optional<ChildUsage> RunSelf(std::vector<std::string> arguments) {
  const auto report = std::filesystem::temp_directory_path() /
                      ("bouncecal_bench_report_" + std::to_string(getpid()) + ".txt");
  arguments.insert(arguments.begin(), {"/proc/self/exe", "--report", report.string()});
  std::vector<char*> argv;
  for (auto& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ) != 0) {
    return std::nullopt;
  }
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return std::nullopt;
  }
  ChildUsage result{Seconds(usage.ru_utime) + Seconds(usage.ru_stime), -1};
  if (std::FILE* file = std::fopen(report.c_str(), "r")) {
    if (std::fscanf(file, "%lf", &result.peak_rss_mib) != 1) result.peak_rss_mib = -1;
    std::fclose(file);
  }
  std::filesystem::remove(report);
  if (result.peak_rss_mib < 0) return std::nullopt;
  return result;
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
  // A fresh process that only starts and exits: the resident memory every run pays (program,
  // shared libraries), to tell it apart from what the analysis adds.
  const auto baseline = RunSelf({"--baseline"});
  std::optional<ChildUsage> analysis;
  for (auto _ : state) {
    analysis = RunSelf({"--analyze-file", path.string()});
    if (!analysis) {
      state.SkipWithError("the analysis child failed");
      break;
    }
    state.SetIterationTime(analysis->cpu_s);
  }
  std::filesystem::remove(path);
  if (!analysis || !baseline) return;
  const double speed = 600.0 / analysis->cpu_s;
  state.counters["audio_s_per_cpu_s"] = speed;
  state.counters["peak_rss_MiB"] = analysis->peak_rss_mib;
  state.counters["baseline_rss_MiB"] = baseline->peak_rss_mib;
  std::printf(
      "10-minute 48 kHz mono 16-bit WAV, read + detect + sequences in a fresh process: "
      "%.0f s of audio per CPU second (%.2f CPU s), peak RSS %.1f MiB (%.1f MiB for a process "
      "that does nothing)\n",
      speed, analysis->cpu_s, analysis->peak_rss_mib, baseline->peak_rss_mib);
}
BENCHMARK(BM_AnalyzeFile10min)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

// The child's work for BM_AnalyzeFile10min: one file analysis (or nothing, for the baseline),
// then its peak resident set written to the report file.
int RunChild(const char* report, const char* path) {
  if (path != nullptr) {
    const auto detection = bouncecal::audio::DetectImpactsInFile(path);
    const auto grouping = bouncecal::audio::FindBounceSequences(detection.detection.impacts);
    std::printf("impacts %zu sequences %zu\n", detection.detection.impacts.size(),
                grouping.sequences.size());
  }
  std::FILE* file = std::fopen(report, "w");
  if (file == nullptr) return 1;
  std::fprintf(file, "%.3f\n", PeakRssMiB());
  return std::fclose(file) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 4 && std::strcmp(argv[1], "--report") == 0) {
    if (std::strcmp(argv[3], "--baseline") == 0) return RunChild(argv[2], nullptr);
    if (argc == 5 && std::strcmp(argv[3], "--analyze-file") == 0) return RunChild(argv[2], argv[4]);
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
