#include <benchmark/benchmark.h>

#include "bouncecal/calibrate/restitution.h"

namespace {

// The restitution analysis runs inside every calibration objective evaluation that uses
// measured intervals, so its cost per impact matters.
void BM_AnalyzeRestitution(benchmark::State& state) {
  std::vector<bouncecal::calibrate::TimedImpact> impacts;
  double t = 0.2, flight = 0.4;
  for (int k = 0; k < state.range(0); ++k) {
    impacts.push_back({t, 20e-6});
    flight *= 0.8;
    t += flight;
  }
  bouncecal::calibrate::RestitutionOptions options;
  options.drop_height_m = 0.2;
  for (auto _ : state) {
    benchmark::DoNotOptimize(bouncecal::calibrate::AnalyzeRestitution(impacts, options));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_AnalyzeRestitution)->Arg(10)->Arg(30)->Arg(100);

}  // namespace
