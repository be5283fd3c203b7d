#include "plot/gnuplot_plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bouncecal/error.h"

namespace bouncecal::apps {
namespace {

PlotPanel SinePanel() {
  PlotPanel panel{"test", "time t (s)", "height h (m)", {}, {}, {}, false, "top right"};
  PlotSeries series{"it's a curve", {0, 1, 2, 3}, {0, 1, 0, -1}, {}, SeriesStyle::kLines, false};
  panel.series.push_back(series);
  series.style = SeriesStyle::kErrorBars;
  series.y_error = {0.1, 0.1, 0.1, 0.1};
  panel.series.push_back(series);
  return panel;
}

TEST(RenderPlot, WritesAPngWithItsSignatureAndLeavesNoTemporaryFiles) {
  const auto folder = std::filesystem::temp_directory_path() / "bouncecal_plot_test_png";
  std::filesystem::create_directories(folder);
  const auto target = folder / "figure.png";
  RenderPlot(target, {SinePanel(), SinePanel()});
  std::ifstream in(target, std::ios::binary);
  char signature[4] = {};
  in.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder),
                          std::filesystem::directory_iterator()),
            1);
  std::filesystem::remove_all(folder);
}

TEST(RenderPlot, WritesAnSvg) {
  const auto target = std::filesystem::temp_directory_path() / "bouncecal_plot_test.svg";
  RenderPlot(target, {SinePanel()});
  std::ifstream in(target);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  std::filesystem::remove(target);
}

TEST(RenderPlot, RejectsAnUnknownExtensionAndEmptyPanels) {
  EXPECT_THROW(RenderPlot("figure.pdf", {SinePanel()}), ConfigError);
  EXPECT_THROW(RenderPlot("figure.png", {}), ConfigError);
}

TEST(RenderPlot, UnwritableTargetIsAnOutputError) {
  EXPECT_THROW(RenderPlot("/nonexistent/folder/figure.png", {SinePanel()}), OutputError);
}

}  // namespace
}  // namespace bouncecal::apps
