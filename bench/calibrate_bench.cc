#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bouncecal/calibrate/ball_preset.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/dem/drop.h"
#include "bouncecal/random_stream.h"

namespace {

namespace calibrate = bouncecal::calibrate;
namespace dem = bouncecal::dem;

// A recording's impact times as the analyzer would write them: a simulated gamma_n = 0.41 drop
// from 0.2 m (30 impacts) with 10 us Gaussian onset noise, one CSV per seed.
std::filesystem::path ImpactCsv(int seed) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("bouncecal_bench_drop_" + std::to_string(seed) + ".csv");
  dem::DropOptions drop;
  drop.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.41}}};
  drop.max_impacts = 30;
  bouncecal::RandomStream random(static_cast<std::uint64_t>(seed), 0);
  std::ofstream out(path);
  out.precision(17);
  out << "onset_s,onset_uncertainty_s\n";
  for (const auto& impact : dem::SimulateDrop(drop).impacts)
    out << impact.time_s + 0.5 + 10e-6 * random.Gaussian() << ",1e-5\n";
  return path;
}

// The whole `bouncecal calibrate` of the given inputs at the default accuracy: load -> fit
// (with the analytic check and the uncertainty model) -> material card written.
void Calibrate(const std::vector<std::filesystem::path>& inputs, calibrate::FitOptions options,
               const std::filesystem::path& card) {
  const auto sequences = calibrate::LoadSequences(inputs);
  const auto summary = calibrate::Fit(sequences, options);
  calibrate::WriteMaterialCard(
      card, calibrate::MakeMaterialCard(summary, options, inputs, std::time(nullptr)));
  benchmark::DoNotOptimize(summary.residual);
}

// The options of `bouncecal calibrate --ball steel-10mm --card ...`, with or without the drop
// height the synthetic recordings were made with.
calibrate::FitOptions CardOptions(bool drop_height_known) {
  calibrate::FitOptions options;
  options.drop.ball = calibrate::FindBallPreset("steel-10mm").ToBall();
  options.ball_given = true;
  options.ball_preset = "steel-10mm";
  options.drop.drop_height_m = 0.2;
  options.drop_height_given = drop_height_known;
  return options;
}

// Arguments: objective (0 mean-energy-loss, 1 intervals), threads (which matter for
// --compare-laws only since the interval stopped being a bootstrap: kept to show it).
void BM_CalibrateOneRecording(benchmark::State& state) {
  const std::vector<std::filesystem::path> inputs = {ImpactCsv(1)};
  auto options = CardOptions(false);
  options.objective = state.range(0) == 0 ? calibrate::FitObjective::kMeanEnergyLoss
                                          : calibrate::FitObjective::kIntervals;
  options.uncertainty.threads = static_cast<int>(state.range(1));
  const auto card = std::filesystem::temp_directory_path() / "bouncecal_bench_card.json";
  for (auto _ : state) Calibrate(inputs, options, card);
}
BENCHMARK(BM_CalibrateOneRecording)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->ArgNames({"objective", "threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The README's main job: the shipped 48 kHz sample through the audio stage (load, detect,
// bounce sequence) -> fit -> card.
void BM_CalibrateShippedSampleWav(benchmark::State& state) {
  const std::vector<std::filesystem::path> inputs = {std::filesystem::path(BOUNCECAL_SOURCE_DIR) /
                                                     "samples" / "steel_ball_h0.2m.wav"};
  const auto options = CardOptions(true);
  const auto card = std::filesystem::temp_directory_path() / "bouncecal_bench_card_wav.json";
  for (auto _ : state) Calibrate(inputs, options, card);
}
BENCHMARK(BM_CalibrateShippedSampleWav)->UseRealTime()->Unit(benchmark::kMillisecond);

// Five recordings fitted jointly (the paper averaged five), one or two threads.
void BM_CalibrateFiveRecordings(benchmark::State& state) {
  std::vector<std::filesystem::path> inputs;
  for (int seed = 1; seed <= 5; ++seed) inputs.push_back(ImpactCsv(seed));
  auto options = CardOptions(false);
  options.uncertainty.threads = static_cast<int>(state.range(0));
  const auto card = std::filesystem::temp_directory_path() / "bouncecal_bench_card5.json";
  for (auto _ : state) Calibrate(inputs, options, card);
}
BENCHMARK(BM_CalibrateFiveRecordings)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Real recordings by others through the whole command (BOUNCECAL_SHARED_DIR/recordings, when
// present; docs/recordings.md): the longest
// one (ub-mth337 ping-pong, 12 s, 59 impacts) alone, and five of them fitted jointly. Five
// different balls make no material, but they are the CPU cost of five real files.
std::vector<std::filesystem::path> SharedRecordings(int count) {
  const auto folder = std::filesystem::path(BOUNCECAL_SHARED_DIR) / "recordings";
  const std::vector<std::filesystem::path> all = {
      folder / "ub-mth337/pingpong.wav", folder / "eeps-pingpong/pingpong.wav",
      folder / "fr4nci-rimbalzi/Audio.wav", folder / "ub-mth337/rubberball.wav",
      folder / "alessia-rimbalzi/rimbalzi.wav"};
  return {all.begin(), all.begin() + count};
}

void BM_CalibrateSharedRecordings(benchmark::State& state) {
  const auto inputs = SharedRecordings(static_cast<int>(state.range(0)));
  for (const auto& input : inputs) {
    if (!std::filesystem::exists(input)) {
      state.SkipWithError("shared recordings absent");
      return;
    }
  }
  const auto options = CardOptions(false);
  const auto card = std::filesystem::temp_directory_path() / "bouncecal_bench_card_shared.json";
  for (auto _ : state) Calibrate(inputs, options, card);
}
BENCHMARK(BM_CalibrateSharedRecordings)
    ->Arg(1)
    ->Arg(5)
    ->ArgNames({"recordings"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// One objective evaluation's drop: the unit cost of every fit.
void BM_SimulateDropForFit(benchmark::State& state) {
  dem::DropOptions drop;
  drop.law = {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", 0.41}}};
  drop.max_impacts = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(dem::SimulateDrop(drop).impacts.size());
}
BENCHMARK(BM_SimulateDropForFit)->Arg(4)->Arg(30)->Unit(benchmark::kMicrosecond);

}  // namespace
