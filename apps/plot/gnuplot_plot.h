#ifndef BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_
#define BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bouncecal::apps {

// kBand fills between y and y_high (a min/max envelope of a decimated waveform).
enum class SeriesStyle { kLines, kPoints, kLinesPoints, kErrorBars, kBand };

// One curve: x and y (same length) and, for kErrorBars, a one-sigma error per point; for kBand,
// the upper edge y_high per point.
struct PlotSeries {
  std::string title;  // legend entry
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> y_error;
  SeriesStyle style = SeriesStyle::kLines;
  bool dashed = false;
  std::vector<double> y_high = {};
  // gnuplot point type for kPoints (7 filled circle, 9 up triangle, 11 down triangle, 2 cross);
  // distinct shapes keep marker kinds apart in greyscale prints too.
  int point_type = 7;
  double point_size = 1.0;
};

// One set of axes. Labels must carry their unit, e.g. "time t (s)".
struct PlotPanel {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
  std::optional<std::pair<double, double>> x_range;
  std::optional<std::pair<double, double>> y_range;
  bool log_y = false;
  std::string legend_position = "top right";  // gnuplot "set key" position words
  // x counts things (impact number k): whole-number ticks, one per value up to 20.
  bool integer_x = false;
};

struct PlotOptions {
  int width_px = 1000;
  int height_px_per_panel = 420;  // panels stack vertically
};

// ConfigError unless the file ends in .png or .svg; commands call it before any work so a typo
// does not cost a whole run.
void CheckPlotTarget(const std::filesystem::path& target);

// Renders the panels with gnuplot (pngcairo for .png, svg for .svg): data and script go to a
// private temporary folder, gnuplot draws there, and the image is moved into place atomically,
// so a failed plot never leaves a half-written file. Throws ConfigError for another extension or
// an empty/mismatched series, OutputError when gnuplot is missing, fails, or the target cannot be
// written (the message carries gnuplot's first error line).
void RenderPlot(const std::filesystem::path& target, const std::vector<PlotPanel>& panels,
                const PlotOptions& options = {});

// The same figure as an <svg> element (no XML declaration), for inlining into HTML; throws like
// RenderPlot.
std::string RenderSvgElement(const std::vector<PlotPanel>& panels, const PlotOptions& options = {});

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_
