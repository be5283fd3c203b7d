#ifndef BOUNCECAL_APPS_CALIBRATE_REPORT_H_
#define BOUNCECAL_APPS_CALIBRATE_REPORT_H_

#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {

// The terminal report of a fit: recordings, fitted parameters with their interval, the analytic
// check, why NLopt stopped, evaluations, residual and time.
// Printed to `out`: stdout, or stderr when a document goes to stdout.
void PrintFit(std::FILE* out, const calibrate::FitSummary& summary,
              const calibrate::FitOptions& options, size_t sequence_count);
// The ranking of --compare-laws.
void PrintComparison(std::FILE* out, const calibrate::LawComparison& comparison,
                     size_t sequence_count);
// Energy loss per impact and flight times per interval, measured (with 1-sigma bars) vs fitted.
// Each sequence's simulated impacts are numbered from the measured impact they stand for.
std::vector<PlotPanel> FitPlotPanels(const calibrate::FitSummary& summary);
// The gamma-eta curve of the analytic check with the measured and fitted points (walton-braun
// under the mean-energy-loss objective only; nullopt where the check does not apply).
std::optional<PlotPanel> GammaEtaPanel(const calibrate::FitSummary& summary);
void PlotFit(const std::filesystem::path& target, const calibrate::FitSummary& summary);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CALIBRATE_REPORT_H_
