#include "plot/gnuplot_plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::apps {
namespace {

using bouncecal::testing::ScratchPath;
using bouncecal::testing::ScratchSubfolder;

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
  const auto folder = ScratchSubfolder("png");
  const auto target = folder / "figure.png";
  RenderPlot(target, {SinePanel(), SinePanel()});
  std::ifstream in(target, std::ios::binary);
  char signature[4] = {};
  in.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(RenderPlot, WritesAnSvg) {
  const auto target = ScratchPath("plot.svg");
  RenderPlot(target, {SinePanel()});
  std::ifstream in(target);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
}

TEST(RenderSvgElement, StartsWithTheSvgElementSoItCanBeInlinedInHtml) {
  const std::string svg = RenderSvgElement({SinePanel()});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(svg.find("<!DOCTYPE"), std::string::npos);
}

TEST(RenderPlot, DrawsAMinMaxBandAndMarkerShapes) {
  PlotPanel panel{"band", "time t (s)", "amplitude (1)", {}, {}, {}, false, "top right"};
  PlotSeries band;
  band.title = "envelope";
  band.style = SeriesStyle::kBand;
  band.x = {0, 1, 2};
  band.y = {-1, -0.5, -0.2};
  band.y_high = {1, 0.5, 0.2};
  panel.series.push_back(band);
  PlotSeries markers;
  markers.title = "impacts";
  markers.style = SeriesStyle::kPoints;
  markers.point_type = 11;
  markers.x = {0.5};
  markers.y = {1.1};
  panel.series.push_back(markers);
  const std::string svg = RenderSvgElement({panel});
  EXPECT_NE(svg.find("envelope"), std::string::npos);
  EXPECT_NE(svg.find("impacts"), std::string::npos);
  band.y_high.pop_back();
  panel.series = {band};
  EXPECT_THROW(RenderSvgElement({panel}), ConfigError);
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
