#ifndef BOUNCECAL_APPS_CALIBRATE_REPORT_H_
#define BOUNCECAL_APPS_CALIBRATE_REPORT_H_

#include <filesystem>

#include "bouncecal/calibrate/fit.h"

namespace bouncecal::apps {

// The terminal report of a fit: recordings, fitted parameters with their interval, the analytic
// check, why NLopt stopped, evaluations, residual and time.
void PrintFit(const calibrate::FitSummary& summary, const calibrate::FitOptions& options,
              size_t sequence_count);
// The ranking of --compare-laws.
void PrintComparison(const calibrate::LawComparison& comparison, size_t sequence_count);
// Energy loss per impact and flight times per interval, measured (with 1-sigma bars) vs fitted.
void PlotFit(const std::filesystem::path& target, const calibrate::FitSummary& summary,
             const calibrate::FitOptions& options);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CALIBRATE_REPORT_H_
