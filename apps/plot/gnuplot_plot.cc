#include "plot/gnuplot_plot.h"

#include <fmt/core.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <sstream>

#include "bouncecal/atomic_file.h"
#include "bouncecal/error.h"

namespace bouncecal::apps {
namespace {

// A private folder that is removed with everything in it on every path out.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "bouncecal-plot-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw OutputError("cannot create a temporary folder for gnuplot in " +
                        std::filesystem::temp_directory_path().string() + "; check TMPDIR");
    }
    path_ = pattern;
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// gnuplot single-quoted strings take no escapes except '' for a quote.
std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    quoted += c;
    if (c == '\'') quoted += '\'';
  }
  return quoted + "'";
}

std::string StyleClause(const PlotSeries& series, int index) {
  const std::string dash = series.dashed ? " dashtype 2" : "";
  const std::string color = fmt::format(" linecolor {}", index + 1);
  switch (series.style) {
    case SeriesStyle::kLines:
      return "with lines linewidth 2" + color + dash;
    case SeriesStyle::kPoints:
      return fmt::format("with points pointtype {} pointsize {}", series.point_type,
                         series.point_size) +
             color;
    case SeriesStyle::kLinesPoints:
      return "with linespoints linewidth 2 pointtype 7 pointsize 0.8" + color + dash;
    case SeriesStyle::kErrorBars:
      return "with yerrorbars pointtype 7 pointsize 1" + color;
    case SeriesStyle::kBand:
      return "with filledcurves fillstyle solid 0.6 noborder" + color;
  }
  return "with lines";
}

void Validate(const std::filesystem::path& target, const std::vector<PlotPanel>& panels) {
  if (panels.empty()) throw ConfigError("a plot needs at least one panel");
  for (const auto& panel : panels) {
    if (panel.series.empty()) {
      throw ConfigError("plot panel '" + panel.title + "' has no series to draw");
    }
    for (const auto& series : panel.series) {
      const bool errors_ok =
          series.style != SeriesStyle::kErrorBars || series.y_error.size() == series.y.size();
      const bool band_ok =
          series.style != SeriesStyle::kBand || series.y_high.size() == series.y.size();
      if (series.x.size() != series.y.size() || !errors_ok || !band_ok) {
        throw ConfigError("plot series '" + series.title + "' has mismatched x/y/error lengths");
      }
    }
  }
  CheckPlotTarget(target);
}

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

namespace {

// Runs gnuplot in a private folder and returns the image bytes; `name` is what error messages
// call the figure.
std::string RenderBytes(const std::string& name, const std::vector<PlotPanel>& panels,
                        const PlotOptions& options, bool svg) {
  TemporaryFolder folder;
  const auto image = folder.path() / (svg ? "plot.svg" : "plot.png");
  const int height_px = options.height_px_per_panel * static_cast<int>(panels.size());

  std::ostringstream script;
  script << (svg ? fmt::format("set terminal svg size {},{} dynamic font 'Sans,12' noenhanced\n",
                               options.width_px, height_px)
                 : fmt::format("set terminal pngcairo size {},{} font 'Sans,11' noenhanced\n",
                               options.width_px, height_px));
  script << "set output " << Quote(image.string()) << "\n";
  script << "set grid\nset key box opaque\n";
  if (panels.size() > 1) script << "set multiplot layout " << panels.size() << ",1\n";
  for (size_t p = 0; p < panels.size(); ++p) {
    const auto& panel = panels[p];
    script << "set title " << Quote(panel.title) << "\n";
    script << "set xlabel " << Quote(panel.x_label) << "\n";
    script << "set ylabel " << Quote(panel.y_label) << "\n";
    script << "set key " << panel.legend_position << "\n";
    script << (panel.log_y ? "set logscale y\n" : "unset logscale y\n");
    const bool few = panel.x_range && panel.x_range->second - panel.x_range->first <= 20;
    script << (panel.integer_x && few ? "set xtics 1\n" : "set xtics autofreq\n");
    script << (panel.integer_x ? "set format x '%.0f'\n" : "set format x '% h'\n");
    script << (panel.x_range ? fmt::format("set xrange [{}:{}]\n", panel.x_range->first,
                                           panel.x_range->second)
                             : "set autoscale x\n");
    script << (panel.y_range ? fmt::format("set yrange [{}:{}]\n", panel.y_range->first,
                                           panel.y_range->second)
                             : "set autoscale y\n");
    script << "plot ";
    for (size_t s = 0; s < panel.series.size(); ++s) {
      const auto& series = panel.series[s];
      const auto data = folder.path() / fmt::format("panel{}_series{}.dat", p, s);
      std::ofstream out(data);
      for (size_t i = 0; i < series.x.size(); ++i) {
        out << fmt::format("{:.9g} {:.9g}", series.x[i], series.y[i]);
        if (series.style == SeriesStyle::kErrorBars)
          out << fmt::format(" {:.9g}", series.y_error[i]);
        if (series.style == SeriesStyle::kBand) out << fmt::format(" {:.9g}", series.y_high[i]);
        out << "\n";
      }
      if (!out) throw OutputError("cannot write plot data to " + data.string());
      const bool three_columns =
          series.style == SeriesStyle::kErrorBars || series.style == SeriesStyle::kBand;
      const std::string columns = three_columns ? "1:2:3" : "1:2";
      script << (s ? ", \\\n     " : "") << Quote(data.string()) << " using " << columns
             << " title " << Quote(series.title) << " " << StyleClause(series, static_cast<int>(s));
    }
    script << "\n";
  }
  if (panels.size() > 1) script << "unset multiplot\n";
  script << "unset output\n";

  const auto script_path = folder.path() / "plot.gp";
  const auto log_path = folder.path() / "gnuplot.log";
  std::ofstream(script_path) << script.str();
  const std::string command = fmt::format("gnuplot {} > {} 2>&1", ShellQuote(script_path.string()),
                                          ShellQuote(log_path.string()));
  const int status = std::system(command.c_str());
  if (status != 0 || !std::filesystem::exists(image)) {
    std::ifstream log(log_path);
    std::string first_error;
    for (std::string line; std::getline(log, line);) {
      if (!line.empty()) {
        first_error = line;
        break;
      }
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
      first_error = "gnuplot not found; install it (Debian package gnuplot-nox)";
    }
    throw OutputError("cannot render plot '" + name + "': " + first_error);
  }
  std::ifstream rendered(image, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(rendered)), std::istreambuf_iterator<char>());
}

}  // namespace

void CheckPlotTarget(const std::filesystem::path& target) {
  std::string extension = target.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".png" && extension != ".svg") {
    throw ConfigError("--plot '" + target.string() + "' must end in .png or .svg");
  }
}

void RenderPlot(const std::filesystem::path& target, const std::vector<PlotPanel>& panels,
                const PlotOptions& options) {
  Validate(target, panels);
  std::string extension = target.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  WriteFileAtomically(target, RenderBytes(target.string(), panels, options, extension == ".svg"));
}

std::string RenderSvgElement(const std::vector<PlotPanel>& panels, const PlotOptions& options) {
  Validate("inline.svg", panels);
  const std::string svg = RenderBytes("inline SVG", panels, options, true);
  // Drop the XML declaration and DOCTYPE: inside HTML only the <svg> element is allowed.
  const auto start = svg.find("<svg");
  if (start == std::string::npos) throw OutputError("gnuplot produced no <svg> element");
  return svg.substr(start);
}

}  // namespace bouncecal::apps
