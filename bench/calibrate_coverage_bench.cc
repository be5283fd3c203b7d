// How often does calibrate's 95 % interval contain the material's gamma_n? Synthetic drops whose
// restitution scatters from impact to impact (calibrate::JitteredDrop) plus onset timing noise are
// fitted as `bouncecal calibrate` fits them by default (walton-braun, eta-bar of the first N
// impacts, no drop height), case after case with its own seed, and the table of
// docs/calibration.md is printed: jitter x impacts used x recordings -> coverage, mean width.
//
//   calibrate_coverage_bench [cases per row (default 400)] [threads (default 2)]
//
// The material's gamma_n is what the same fit returns for a drop without scatter or timing noise
// whose restitution sqrt(1 - eta_m) has the material's mean energy loss eta_m = 1 - E[e_k^2]: the
// quantity an average over ever more impacts converges to, with the fit's own time-step and
// contact-duration bias included (a few 1e-4, see the formula column).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/jittered_drop.h"
#include "bouncecal/worker_pool.h"

namespace {

namespace calibrate = bouncecal::calibrate;

struct Row {
  double jitter = 0.03;       // relative per-impact sd of e
  int first_n = 3;            // impacts averaged
  int recordings = 1;         // fitted jointly
  int impacts = 12;           // onsets per recording
  bool known_height = false;  // --drop-height given
  double between = 0;         // relative per-recording sd of e
  double timing_sigma_s = 20e-6;
};

calibrate::FitOptions Options(const Row& row) {
  calibrate::FitOptions options;
  options.first_n = row.first_n;
  options.first_n_given = true;
  options.analytic_check = false;
  options.uncertainty.threads = 1;
  options.drop.drop_height_m = 0.2;  // unused unless given
  options.drop_height_given = row.known_height;
  return options;
}

calibrate::JitteredDropOptions DropOptions(const Row& row) {
  calibrate::JitteredDropOptions drop;
  drop.restitution = 0.65;
  drop.relative_jitter = row.jitter;
  drop.recording_relative_offset = row.between;
  drop.impacts = row.impacts;
  drop.timing_sigma_s = row.timing_sigma_s;
  return drop;
}

// The fit of the scatter-free, noise-free drop with the material's mean energy loss.
double MaterialGamma(const Row& row) {
  auto drop = DropOptions(row);
  drop.restitution = std::sqrt(1 - calibrate::MaterialEnergyLoss(drop));
  drop.relative_jitter = 0;
  drop.recording_relative_offset = 0;
  drop.timing_sigma_s = 0;
  return calibrate::Fit({calibrate::JitteredDrop(drop)}, Options(row)).parameters[0].value;
}

struct Outcome {
  bool covered = false;
  double width = 0;
  double error = 0;  // fitted - material
};

Outcome RunCase(const Row& row, int index, double truth) {
  std::vector<calibrate::MeasuredSequence> sequences;
  auto drop = DropOptions(row);
  drop.seed = 1000 + static_cast<std::uint64_t>(index);
  for (int r = 0; r < row.recordings; ++r) {
    drop.recording = static_cast<std::uint64_t>(r);
    sequences.push_back(calibrate::JitteredDrop(drop));
  }
  const auto summary = calibrate::Fit(sequences, Options(row));
  const auto& gamma = summary.parameters[0];
  Outcome outcome;
  outcome.error = gamma.value - truth;
  if (gamma.confidence_interval) {
    outcome.covered =
        gamma.confidence_interval->first <= truth && truth <= gamma.confidence_interval->second;
    outcome.width = gamma.confidence_interval->second - gamma.confidence_interval->first;
  }
  return outcome;
}

}  // namespace

int main(int argc, char** argv) {
  const int cases = argc > 1 ? std::atoi(argv[1]) : 400;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  if (argc > 3 || cases < 1 || threads < 1 || threads > 1024) {
    std::fprintf(stderr,
                 "usage: calibrate_coverage_bench [CASES [THREADS]]: CASES per row (>= 1, default "
                 "400), THREADS in [1, 1024] (default 2)\n");
    return 2;
  }
  std::vector<Row> rows;
  for (double jitter : {0.0, 0.003, 0.01, 0.03, 0.05}) {
    for (int first_n : {3, 10}) {
      for (int recordings : {1, 3, 5}) {
        Row row;
        row.jitter = jitter;
        row.first_n = first_n;
        row.recordings = recordings;
        rows.push_back(row);
      }
    }
  }
  // The paper's set-up (height known, first 3, five recordings) and recordings that differ from
  // each other beyond their impacts' scatter.
  for (int recordings : {1, 5}) {
    Row known;
    known.known_height = true;
    known.recordings = recordings;
    rows.push_back(known);
  }
  for (int recordings : {3, 5}) {
    Row between;
    between.between = 0.02;
    between.recordings = recordings;
    rows.push_back(between);
  }

  std::printf(
      "# %d cases per row; e = 0.65, onsets +- 20 us, 12 impacts per recording, walton-braun, "
      "mean-energy-loss, velocity Verlet at 50 steps per contact\n",
      cases);
  std::printf(
      "| jitter of e | between recordings | drop height | impacts used | recordings | material "
      "gamma_n | coverage (95 %% binomial range) | mean width | RMS error | CPU s per case |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  bouncecal::WorkerPool pool(std::max(1, threads));  // one case per item
  for (const auto& row : rows) {
    const double truth = MaterialGamma(row);
    std::vector<Outcome> outcomes(static_cast<size_t>(cases));
    const std::clock_t cpu_start = std::clock();
    pool.ParallelForEach(cases, [&](std::int64_t i) {
      outcomes[static_cast<size_t>(i)] = RunCase(row, static_cast<int>(i), truth);
    });
    const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    int covered = 0;
    double width = 0, squares = 0;
    for (const auto& outcome : outcomes) {
      covered += outcome.covered ? 1 : 0;
      width += outcome.width / cases;
      squares += outcome.error * outcome.error / cases;
    }
    const double coverage = static_cast<double>(covered) / cases;
    // The range a correct 95 % interval's coverage falls in over this many cases (normal
    // approximation of the binomial).
    const double spread = 1.96 * std::sqrt(0.95 * 0.05 / cases);
    std::printf(
        "| %.1f %% | %s | %s | %d | %d | %.4f | %.1f %% (%.1f-%.1f) | %.3g | %.3g | %.4f |\n",
        100 * row.jitter,
        row.between > 0 ? (std::to_string(static_cast<int>(100 * row.between)) + " %").c_str()
                        : "0",
        row.known_height ? "0.2 m" : "not given", row.first_n, row.recordings, truth,
        100 * coverage, 100 * (0.95 - spread), 100 * (0.95 + spread), width, std::sqrt(squares),
        cpu_s / cases);
    std::fflush(stdout);
  }
  return 0;
}
