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

// The paper's drop through a recording chain (automatic oversampling: 8 x 48 kHz) with the
// contact click: the modes are rendered at 384 kHz and decimated by a 557-tap FIR.
void BM_SynthesizeSteelDropThroughLinearPhaseChain(benchmark::State& state) {
  SynthesisOptions options;
  options.chain = bouncecal::audio::RecordingChain{};
  options.click_gain = 0.2;
  Run(state, options);
}
BENCHMARK(BM_SynthesizeSteelDropThroughLinearPhaseChain)->Unit(benchmark::kMillisecond);

// The same with the minimum-phase filter, whose cepstral design costs more than the Kaiser one.
void BM_SynthesizeSteelDropThroughMinimumPhaseChain(benchmark::State& state) {
  SynthesisOptions options;
  options.chain =
      bouncecal::audio::RecordingChain{.phase = bouncecal::audio::AdcFilterPhase::kMinimum};
  options.click_gain = 0.2;
  Run(state, options);
}
BENCHMARK(BM_SynthesizeSteelDropThroughMinimumPhaseChain)->Unit(benchmark::kMillisecond);

// A phone-rate file through the chain: 24 x 16 kHz, the same 384 kHz rendering as at 48 kHz,
// with a three times longer filter over a third of the outputs.
void BM_SynthesizeSteelDropAt16kHzThroughLinearPhaseChain(benchmark::State& state) {
  SynthesisOptions options;
  options.sample_rate_hz = 16000;
  options.chain = bouncecal::audio::RecordingChain{};
  options.click_gain = 0.2;
  Run(state, options);
}
BENCHMARK(BM_SynthesizeSteelDropAt16kHzThroughLinearPhaseChain)->Unit(benchmark::kMillisecond);

// The impaired drop (reverb, noise, hum) through the chain: the reverb tail is convolved at
// 384 kHz.
void BM_SynthesizeSteelDropImpairedThroughLinearPhaseChain(benchmark::State& state) {
  SynthesisOptions options;
  options.reverb = bouncecal::audio::ReverbOptions{};
  options.noise = bouncecal::audio::NoiseOptions{};
  options.hum = bouncecal::audio::HumOptions{};
  options.chain = bouncecal::audio::RecordingChain{};
  options.click_gain = 0.2;
  Run(state, options);
}
BENCHMARK(BM_SynthesizeSteelDropImpairedThroughLinearPhaseChain)->Unit(benchmark::kMillisecond);

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
