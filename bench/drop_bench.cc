#include <benchmark/benchmark.h>

#include "bouncecal/dem/drop.h"

namespace {

using bouncecal::dem::DropOptions;
using bouncecal::dem::Integrator;

// The paper's drop (1 cm steel, k = 1e7 N/m, gamma_n = 0.5, 20 cm) simulated to rest. The
// calibration runs this inside every NLopt objective evaluation, so its cost bounds the fit.
void RunDrop(benchmark::State& state, Integrator integrator, double steps_per_contact,
             bouncecal::dem::ContactLawKind law = bouncecal::dem::ContactLawKind::kWaltonBraun) {
  DropOptions options;
  options.law.kind = law;
  options.integrator = integrator;
  options.steps_per_contact = steps_per_contact;
  std::size_t impacts = 0;
  for (auto _ : state) {
    const auto result = bouncecal::dem::SimulateDrop(options);
    impacts = result.impacts.size();
    benchmark::DoNotOptimize(result.impacts.data());
  }
  state.counters["impacts"] = static_cast<double>(impacts);
}

void BM_DropToRestVerlet50(benchmark::State& state) {
  RunDrop(state, Integrator::kVelocityVerlet, 50);
}
void BM_DropToRestEuler50(benchmark::State& state) {
  RunDrop(state, Integrator::kSymplecticEuler, 50);
}
void BM_DropToRestRungeKutta50(benchmark::State& state) {
  RunDrop(state, Integrator::kRungeKutta4, 50);
}
void BM_DropToRestExact(benchmark::State& state) { RunDrop(state, Integrator::kExact, 50); }
void BM_DropToRestExactDashpot(benchmark::State& state) {
  RunDrop(state, Integrator::kExact, 50, bouncecal::dem::ContactLawKind::kLinearDashpot);
}

BENCHMARK(BM_DropToRestVerlet50)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DropToRestEuler50)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DropToRestRungeKutta50)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DropToRestExact)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DropToRestExactDashpot)->Unit(benchmark::kMicrosecond);

}  // namespace
