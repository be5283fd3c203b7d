// Does the 95 % interval of calibrate cover the material's gamma_n as often as it claims? Synthetic
// drops whose restitution scatters from impact to impact (e = 0.65, 3 % relative jitter, 20 us
// onset noise; calibrate::JitteredDrop) are fitted as `bouncecal calibrate` fits by default
// (walton-braun, eta-bar of the first 3 impacts, no drop height). bench/calibrate_coverage_bench
// measures the full table of docs/calibration.md; this checks two of its rows on fixed seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/jittered_drop.h"

namespace bouncecal {
namespace {

calibrate::FitOptions DefaultFit() {
  calibrate::FitOptions options;
  options.analytic_check = false;  // not part of the interval; saves three drops per fit
  return options;
}

// What the fit gives for a drop without scatter or noise whose restitution has the material's
// mean energy loss: the value ever more impacts converge to, with the fit's own time-step bias.
double MaterialGamma(const calibrate::JitteredDropOptions& material) {
  auto ideal = material;
  ideal.restitution = std::sqrt(1 - calibrate::MaterialEnergyLoss(material));
  ideal.relative_jitter = 0;
  ideal.timing_sigma_s = 0;
  return calibrate::Fit({calibrate::JitteredDrop(ideal)}, DefaultFit()).parameters[0].value;
}

struct Coverage {
  int covered = 0;
  int cases = 0;
  double Fraction() const { return static_cast<double>(covered) / cases; }
};

Coverage Measure(int recordings, int cases) {
  calibrate::JitteredDropOptions material;  // e = 0.65, 3 % jitter, 20 us, 12 impacts
  const double truth = MaterialGamma(material);
  Coverage coverage;
  for (int c = 0; c < cases; ++c) {
    material.seed = 1000 + static_cast<std::uint64_t>(c);
    std::vector<calibrate::MeasuredSequence> sequences;
    for (int r = 0; r < recordings; ++r) {
      material.recording = static_cast<std::uint64_t>(r);
      sequences.push_back(calibrate::JitteredDrop(material));
    }
    const auto interval = calibrate::Fit(sequences, DefaultFit()).parameters[0].confidence_interval;
    ++coverage.cases;
    if (interval && interval->first <= truth && truth <= interval->second) ++coverage.covered;
  }
  return coverage;
}

// A correct 95 % interval covers in Binomial(n, 0.95) of n cases: for n = 200 at least 90 %
// except with probability 1.2e-3, at most 99 % except with probability 4e-4, so the check fails
// for a too narrow interval (the timing-only one of before covers 1 of these 200 cases) and for
// a needlessly wide one. The seeds are fixed, so the outcome is too: 190 of 200 (the table in
// docs/calibration.md has 400 cases of the same row).
TEST(CalibrateCoverage, OneRecordingsIntervalCoversTheMaterialInNinetyFivePercentOfCases) {
  const auto coverage = Measure(1, 200);
  RecordProperty("covered", coverage.covered);
  EXPECT_GE(coverage.Fraction(), 0.90) << coverage.covered << " of " << coverage.cases;
  EXPECT_LE(coverage.Fraction(), 0.99) << coverage.covered << " of " << coverage.cases;
}

// Five recordings (the paper's protocol), 100 cases: at least 90 % fails for a correct interval
// with probability 0.011. No upper bound here: with few recordings the between-recording part of
// the interval is estimated from their spread with 4 degrees of freedom, which makes it cover
// about 97 % when the recordings do not differ (the bench's rows), so 100 of 100 is no defect.
// Measured on these seeds: 99 of 100.
TEST(CalibrateCoverage, FiveRecordingsIntervalCoversTheMaterialInNinetyFivePercentOfCases) {
  const auto coverage = Measure(5, 100);
  RecordProperty("covered", coverage.covered);
  EXPECT_GE(coverage.Fraction(), 0.90) << coverage.covered << " of " << coverage.cases;
}

}  // namespace
}  // namespace bouncecal
