#ifndef BOUNCECAL_APPS_CALIBRATION_HTML_H_
#define BOUNCECAL_APPS_CALIBRATION_HTML_H_

#include <string>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/material_card.h"
#include "report_recordings.h"

namespace bouncecal::apps {

// Everything the calibration report shows; the figures are ready-made <svg> elements.
struct CalibrationReportContent {
  std::string command_line;  // as typed, so the page says how to reproduce it
  calibrate::FitSummary summary;
  calibrate::FitOptions options;
  calibrate::MaterialCard card;
  std::string card_json;  // the card exactly as `calibrate --card` writes it
  std::string fit_json;   // calibrate::ToJson(summary), as `calibrate --json` writes it
  std::vector<std::pair<std::string, std::string>> figures;  // caption, <svg> element
  // Each input's waveform with the impacts, sequences and rejected events (its own section).
  std::vector<RecordingView> recordings;
};

// One self-contained HTML5 page: inline CSS and SVG, no script, no external resource, so it
// opens offline and can be archived with a lab notebook or a paper's supplement.
std::string CalibrationReportHtml(const CalibrationReportContent& content);

// &, <, >, " and ' as entities.
std::string EscapeHtml(const std::string& text);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CALIBRATION_HTML_H_
