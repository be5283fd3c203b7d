#ifndef BOUNCECAL_CALIBRATE_FIT_JSON_H_
#define BOUNCECAL_CALIBRATE_FIT_JSON_H_

#include <nlohmann/json.hpp>
#include <string_view>

#include "bouncecal/calibrate/fit.h"

namespace bouncecal::calibrate {

// The "format" field of each document (docs/json.md has their JSON Schemas).
inline constexpr std::string_view kFitFormat = "bouncecal-fit/1";
inline constexpr std::string_view kLawComparisonFormat = "bouncecal-law-comparison/1";

// The full fit result for `bouncecal calibrate --json`: at least {"law", "parameters",
// "confidence_interval", "analytic": {"energy_loss_mean", "gamma_n"}, "objective", "residual",
// "evaluations", "stop_reason"} (issue 4), plus the check, the information criteria and
// per-recording measured and simulated sequences. No run times (fit_time_s, total_time_s): the
// same input and seed give byte-identical JSON (issue 7); the terminal report prints them.
nlohmann::json ToJson(const FitSummary& summary);

// {"format", "criterion": "bic", "ranking": [fit, ...]} best first (by BIC), each fit as
// ToJson(FitSummary) without "format", plus "delta_bic".
nlohmann::json ToJson(const LawComparison& comparison);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_FIT_JSON_H_
