#include <benchmark/benchmark.h>

#include "bouncecal/audio/synthesize.h"

namespace {

using bouncecal::audio::SynthesisOptions;

// Synthesis feeds every detector test and calibration round trip; the figure that matters is
// seconds of audio rendered per second of CPU ("audio_s" as a rate).
void Run(benchmark::State& state, const SynthesisOptions& options) {
  double audio_s = 0.0;
  for (auto _ : state) {
    const auto recording = bouncecal::audio::SynthesizeBounces(options);
    audio_s = recording.channels[0].duration_s() * static_cast<double>(recording.channels.size());
    benchmark::DoNotOptimize(recording.channels[0].samples.data());
  }
  state.counters["audio_s"] =
      benchmark::Counter(audio_s, benchmark::Counter::kIsIterationInvariantRate);
}

// The paper's drop on the 61-mode steel plate, no impairments.
void BM_SynthesizeSteelDrop(benchmark::State& state) { Run(state, SynthesisOptions{}); }
BENCHMARK(BM_SynthesizeSteelDrop)->Unit(benchmark::kMillisecond);

// The same with reverb, noise and hum: FFT convolution and noise generation added.
void BM_SynthesizeSteelDropImpaired(benchmark::State& state) {
  SynthesisOptions options;
  options.reverb = bouncecal::audio::ReverbOptions{};
  options.noise = bouncecal::audio::NoiseOptions{};
  options.hum = bouncecal::audio::HumOptions{};
  Run(state, options);
}
BENCHMARK(BM_SynthesizeSteelDropImpaired)->Unit(benchmark::kMillisecond);

// Ten minutes of repeated drops (the detector's long-file benchmark input): mode states are
// dropped between drops, so the cost follows the sound, not the silence.
void BM_SynthesizeTenMinutesOfDrops(benchmark::State& state) {
  SynthesisOptions options;
  options.drop.drop_count = 200;
  options.drop.gap_between_drops_s = 1.5;
  options.noise = bouncecal::audio::NoiseOptions{};
  options.duration_s = 600.0;
  Run(state, options);
}
BENCHMARK(BM_SynthesizeTenMinutesOfDrops)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
