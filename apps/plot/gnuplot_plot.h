#ifndef BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_
#define BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bouncecal::apps {

enum class SeriesStyle { kLines, kPoints, kLinesPoints, kErrorBars };

// One curve: x and y (same length) and, for kErrorBars, a one-sigma error per point.
struct PlotSeries {
  std::string title;  // legend entry
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> y_error;
  SeriesStyle style = SeriesStyle::kLines;
  bool dashed = false;
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
};

struct PlotOptions {
  int width_px = 1000;
  int height_px_per_panel = 420;  // panels stack vertically
};

// Renders the panels with gnuplot (pngcairo for .png, svg for .svg): data and script go to a
// private temporary folder, gnuplot draws there, and the image is moved into place atomically,
// so a failed plot never leaves a half-written file. Throws ConfigError for another extension or
// an empty/mismatched series, OutputError when gnuplot is missing, fails, or the target cannot be
// written (the message carries gnuplot's first error line).
void RenderPlot(const std::filesystem::path& target, const std::vector<PlotPanel>& panels,
                const PlotOptions& options = {});

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PLOT_GNUPLOT_PLOT_H_
