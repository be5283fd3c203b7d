#ifndef BOUNCECAL_CALIBRATE_MINIMIZER_H_
#define BOUNCECAL_CALIBRATE_MINIMIZER_H_

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bouncecal::calibrate {

// Derivative-free local methods from NLopt (Johnson, "The NLopt nonlinear-optimization package").
// The calibration objective is a DEM simulation: no gradient, slightly noisy in the parameters
// (impact onsets are interpolated within a time step), cheap enough for a few hundred calls.
//  - kBobyqa: Powell's BOBYQA (2009), quadratic models within bounds; fewest evaluations on
//    smooth objectives, hence the default.
//  - kCobyla: Powell's COBYLA, linear models; more robust to kinks, slower.
//  - kNelderMead: the simplex method, most tolerant of noise, slowest.
enum class LocalMethod { kBobyqa, kCobyla, kNelderMead };
std::string_view ToString(LocalMethod method);
// Accepts "bobyqa", "cobyla", "nelder-mead"; throws ConfigError listing them otherwise.
LocalMethod LocalMethodFromString(std::string_view name);

// Why the search stopped (NLopt's nlopt_result, without the error codes that become exceptions).
enum class MinimizerStop {
  kSuccess,
  kStopValueReached,
  kFunctionToleranceReached,
  kParameterToleranceReached,
  kMaxEvaluationsReached,
  kMaxTimeReached,
  kRoundoffLimited,  // NLopt could not make progress because of round-off: the best point is kept
  kFailure,          // NLopt reported a generic failure; the best point seen is kept
};
std::string_view ToString(MinimizerStop stop);
// True for the stops that mean the tolerances were met (not a budget or a failure).
bool IsConverged(MinimizerStop stop);

struct MinimizerOptions {
  LocalMethod local_method = LocalMethod::kBobyqa;
  // Evaluations spent first in NLopt's DIRECT-L global search over the whole box (Gablonsky &
  // Kelley 2001; deterministic). The local method then starts from the best point DIRECT-L
  // found. 0 skips the global stage: right for objectives known to be unimodal.
  int global_evaluations = 0;
  // Local stage stops when a step changes every coordinate by less than this fraction of the
  // box width (NLopt xtol_abs per coordinate).
  double parameter_tolerance = 1e-5;
  // ... or when the objective changes by less than this (absolute; 0 disables).
  double function_tolerance = 0;
  // Total budget over both stages.
  int max_evaluations = 300;
  // Wall-clock budget over both stages; 0 means none.
  double max_time_s = 0;
  // First local step as a fraction of the box width.
  double initial_step_fraction = 0.1;
};

struct MinimizerSummary {
  std::vector<double> x;  // best point seen (always inside the bounds)
  double value = 0;       // objective at x
  MinimizerStop stop = MinimizerStop::kFailure;
  std::string message;  // one human sentence on why the search stopped
  int evaluations = 0;  // objective calls over both stages
  int global_evaluations = 0;
  double time_s = 0;  // wall clock
};

using MinimizerObjective = std::function<double(std::span<const double>)>;

// Owns one nlopt::opt per stage and releases it on every path; an exception thrown by the
// objective stops the search and is rethrown unchanged to the caller (NLopt would otherwise
// swallow it into a generic failure). Throws ConfigError for inconsistent bounds or options.
class BoundedMinimizer {
 public:
  BoundedMinimizer(std::vector<double> lower, std::vector<double> upper,
                   MinimizerOptions options = {});

  // x0 is clamped into the box. Non-finite objective values count as +infinity so the search
  // steers away from them.
  MinimizerSummary Minimize(const MinimizerObjective& objective, std::vector<double> x0) const;

  const MinimizerOptions& options() const { return options_; }

 private:
  std::vector<double> lower_;
  std::vector<double> upper_;
  MinimizerOptions options_;
};

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_MINIMIZER_H_
