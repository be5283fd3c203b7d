#include "bouncecal/calibrate/minimizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <nlopt.hpp>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;

// State shared with the C trampoline: the user's objective, the best point over both stages and
// an exception to carry across NLopt's C frames.
struct EvaluationContext {
  const MinimizerObjective* objective = nullptr;
  std::vector<double> best_x;
  double best_value = std::numeric_limits<double>::infinity();
  int evaluations = 0;
  std::exception_ptr error;
};

double Trampoline(unsigned n, const double* x, double* /*gradient*/, void* data) {
  auto* context = static_cast<EvaluationContext*>(data);
  double value = 0;
  try {
    value = (*context->objective)(std::span<const double>(x, n));
  } catch (...) {
    context->error = std::current_exception();
    throw nlopt::forced_stop();
  }
  ++context->evaluations;
  if (!std::isfinite(value)) value = std::numeric_limits<double>::max();
  if (value < context->best_value || context->best_x.empty()) {
    context->best_value = value;
    context->best_x.assign(x, x + n);
  }
  return value;
}

nlopt::algorithm ToNlopt(LocalMethod method) {
  switch (method) {
    case LocalMethod::kBobyqa:
      return nlopt::LN_BOBYQA;
    case LocalMethod::kCobyla:
      return nlopt::LN_COBYLA;
    case LocalMethod::kNelderMead:
      return nlopt::LN_NELDERMEAD;
  }
  return nlopt::LN_BOBYQA;
}

MinimizerStop FromNlopt(nlopt::result result) {
  switch (result) {
    case nlopt::SUCCESS:
      return MinimizerStop::kSuccess;
    case nlopt::STOPVAL_REACHED:
      return MinimizerStop::kStopValueReached;
    case nlopt::FTOL_REACHED:
      return MinimizerStop::kFunctionToleranceReached;
    case nlopt::XTOL_REACHED:
      return MinimizerStop::kParameterToleranceReached;
    case nlopt::MAXEVAL_REACHED:
      return MinimizerStop::kMaxEvaluationsReached;
    case nlopt::MAXTIME_REACHED:
      return MinimizerStop::kMaxTimeReached;
    case nlopt::ROUNDOFF_LIMITED:
      return MinimizerStop::kRoundoffLimited;
    default:
      return MinimizerStop::kFailure;
  }
}

std::string StopMessage(MinimizerStop stop, const MinimizerOptions& options) {
  switch (stop) {
    case MinimizerStop::kSuccess:
      return "NLopt reported success";
    case MinimizerStop::kStopValueReached:
      return "the objective reached its stop value";
    case MinimizerStop::kFunctionToleranceReached:
      return "the objective changed by less than " + std::to_string(options.function_tolerance) +
             " between steps";
    case MinimizerStop::kParameterToleranceReached:
      return "every parameter moved by less than " + std::to_string(options.parameter_tolerance) +
             " of its range between steps";
    case MinimizerStop::kMaxEvaluationsReached:
      return "the budget of " + std::to_string(options.max_evaluations) +
             " evaluations ran out before the tolerances were met";
    case MinimizerStop::kMaxTimeReached:
      return "the time budget of " + std::to_string(options.max_time_s) +
             " s ran out before the tolerances were met";
    case MinimizerStop::kRoundoffLimited:
      return "round-off in the objective stopped further progress (best point kept)";
    case MinimizerStop::kFailure:
      return "NLopt failed (best point seen kept)";
  }
  return "unknown";
}

// Runs one NLopt stage; NLopt's error results become a stop reason, not an exception, because the
// best point seen so far is still a valid answer.
MinimizerStop RunStage(nlopt::opt& optimizer, EvaluationContext& context, std::vector<double>& x) {
  optimizer.set_min_objective(Trampoline, &context);
  double value = 0;
  try {
    return FromNlopt(optimizer.optimize(x, value));
  } catch (const nlopt::forced_stop&) {
    if (context.error) std::rethrow_exception(context.error);
    return MinimizerStop::kFailure;
  } catch (const nlopt::roundoff_limited&) {
    return MinimizerStop::kRoundoffLimited;
  } catch (const std::invalid_argument& error) {
    throw ConfigError(std::string("NLopt rejected the search set-up: ") + error.what());
  } catch (const std::runtime_error&) {
    if (context.error) std::rethrow_exception(context.error);
    return MinimizerStop::kFailure;
  }
}

}  // namespace

std::string_view ToString(LocalMethod method) {
  switch (method) {
    case LocalMethod::kBobyqa:
      return "bobyqa";
    case LocalMethod::kCobyla:
      return "cobyla";
    case LocalMethod::kNelderMead:
      return "nelder-mead";
  }
  return "unknown";
}

LocalMethod LocalMethodFromString(std::string_view name) {
  for (auto method : {LocalMethod::kBobyqa, LocalMethod::kCobyla, LocalMethod::kNelderMead}) {
    if (name == ToString(method)) return method;
  }
  throw ConfigError("unknown local optimiser '" + std::string(name) +
                    "'; use one of bobyqa, cobyla, nelder-mead");
}

std::string_view ToString(MinimizerStop stop) {
  switch (stop) {
    case MinimizerStop::kSuccess:
      return "success";
    case MinimizerStop::kStopValueReached:
      return "stop-value-reached";
    case MinimizerStop::kFunctionToleranceReached:
      return "function-tolerance-reached";
    case MinimizerStop::kParameterToleranceReached:
      return "parameter-tolerance-reached";
    case MinimizerStop::kMaxEvaluationsReached:
      return "max-evaluations-reached";
    case MinimizerStop::kMaxTimeReached:
      return "max-time-reached";
    case MinimizerStop::kRoundoffLimited:
      return "roundoff-limited";
    case MinimizerStop::kFailure:
      return "failure";
  }
  return "unknown";
}

bool IsConverged(MinimizerStop stop) {
  return stop == MinimizerStop::kSuccess || stop == MinimizerStop::kStopValueReached ||
         stop == MinimizerStop::kFunctionToleranceReached ||
         stop == MinimizerStop::kParameterToleranceReached;
}

BoundedMinimizer::BoundedMinimizer(std::vector<double> lower, std::vector<double> upper,
                                   MinimizerOptions options)
    : lower_(std::move(lower)), upper_(std::move(upper)), options_(options) {
  if (lower_.empty() || lower_.size() != upper_.size()) {
    throw ConfigError("minimizer bounds must be non-empty and of equal length (got " +
                      std::to_string(lower_.size()) + " lower, " + std::to_string(upper_.size()) +
                      " upper)");
  }
  for (size_t i = 0; i < lower_.size(); ++i) {
    if (!std::isfinite(lower_[i]) || !std::isfinite(upper_[i]) || !(lower_[i] < upper_[i])) {
      throw ConfigError("minimizer bound " + std::to_string(i) + " must be finite with lower < " +
                        "upper, got [" + std::to_string(lower_[i]) + ", " +
                        std::to_string(upper_[i]) + "]");
    }
  }
  if (options_.max_evaluations < 1 || options_.global_evaluations < 0 ||
      options_.global_evaluations >= options_.max_evaluations) {
    throw ConfigError("minimizer budget: need max_evaluations >= 1 and 0 <= global_evaluations < " +
                      std::string("max_evaluations, got ") +
                      std::to_string(options_.max_evaluations) + " and " +
                      std::to_string(options_.global_evaluations));
  }
  if (!(options_.parameter_tolerance > 0) || !(options_.function_tolerance >= 0) ||
      !(options_.max_time_s >= 0) || !(options_.initial_step_fraction > 0) ||
      !(options_.initial_step_fraction <= 1)) {
    throw ConfigError(
        "minimizer tolerances: parameter_tolerance must be > 0, function_tolerance and "
        "max_time_s >= 0, initial_step_fraction in (0, 1]");
  }
}

MinimizerSummary BoundedMinimizer::Minimize(const MinimizerObjective& objective,
                                            std::vector<double> x0) const {
  const size_t n = lower_.size();
  if (x0.size() != n) {
    throw ConfigError("minimizer start point has " + std::to_string(x0.size()) +
                      " coordinates, the bounds have " + std::to_string(n));
  }
  for (size_t i = 0; i < n; ++i) {
    x0[i] = std::isfinite(x0[i]) ? std::clamp(x0[i], lower_[i], upper_[i])
                                 : 0.5 * (lower_[i] + upper_[i]);
  }
  const auto start = Clock::now();
  auto elapsed_s = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  EvaluationContext context;
  context.objective = &objective;
  MinimizerSummary summary;

  std::vector<double> x_tolerance(n), step(n);
  for (size_t i = 0; i < n; ++i) {
    const double width = upper_[i] - lower_[i];
    x_tolerance[i] = options_.parameter_tolerance * width;
    step[i] = options_.initial_step_fraction * width;
  }

  std::vector<double> x = x0;
  if (options_.global_evaluations > 0) {
    nlopt::opt global(nlopt::GN_DIRECT_L, static_cast<unsigned>(n));
    global.set_lower_bounds(lower_);
    global.set_upper_bounds(upper_);
    global.set_maxeval(options_.global_evaluations);
    global.set_xtol_abs(x_tolerance);
    if (options_.max_time_s > 0) global.set_maxtime(options_.max_time_s);
    RunStage(global, context, x);
    summary.global_evaluations = context.evaluations;
    if (!context.best_x.empty()) x = context.best_x;
  }

  const int remaining = options_.max_evaluations - context.evaluations;
  const double time_left_s = options_.max_time_s > 0 ? options_.max_time_s - elapsed_s() : 0;
  if (options_.max_time_s > 0 && time_left_s <= 0) {
    summary.stop = MinimizerStop::kMaxTimeReached;
  } else if (remaining <= 0) {
    summary.stop = MinimizerStop::kMaxEvaluationsReached;
  } else {
    nlopt::opt local(ToNlopt(options_.local_method), static_cast<unsigned>(n));
    local.set_lower_bounds(lower_);
    local.set_upper_bounds(upper_);
    local.set_maxeval(remaining);
    local.set_xtol_abs(x_tolerance);
    if (options_.function_tolerance > 0) local.set_ftol_abs(options_.function_tolerance);
    if (time_left_s > 0) local.set_maxtime(time_left_s);
    // Keep the first step inside the box so BOBYQA's initial interpolation points are valid.
    for (size_t i = 0; i < n; ++i) {
      const double room = std::max(x[i] - lower_[i], upper_[i] - x[i]);
      step[i] = std::min(step[i], room);
    }
    local.set_initial_step(step);
    summary.stop = RunStage(local, context, x);
  }

  summary.x = context.best_x.empty() ? x : context.best_x;
  summary.value = context.best_value;
  summary.evaluations = context.evaluations;
  summary.message = StopMessage(summary.stop, options_);
  summary.time_s = elapsed_s();
  return summary;
}

}  // namespace bouncecal::calibrate
