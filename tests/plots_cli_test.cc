// --plot on analyze and simulate drop: the figures exist, are the right format and show what the
// run found (counts in the legend come from the same data the tables print).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

class PlotsCli : public ::testing::Test {
 protected:
  const ScratchFolder folder_;
};

TEST_F(PlotsCli, AnalyzePlotMarksEveryImpactTheTableReportsAndDrawsEtaVsK) {
  // The legend counts come from the same analysis as --json: every impact of every sequence is
  // marked, every rejected event too.
  const auto svg = folder_ / "analyze.svg";
  const auto json_path = folder_ / "analyze.json";
  const auto run = RunBouncecal("analyze " + (SourceDir() / "samples/pingpong_hard.wav").string() +
                                " --json " + json_path.string() + " --plot " + svg.string());
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const auto json = nlohmann::json::parse(ReadFileText(json_path))["recordings"][0];
  std::size_t in_sequences = 0;
  for (const auto& sequence : json["sequences"]) in_sequences += sequence["onsets_s"].size();
  ASSERT_GT(in_sequences, 2u);
  const std::string text = ReadFileText(svg);
  EXPECT_NE(text.find("impact (" + std::to_string(in_sequences) + ")"), std::string::npos);
  if (!json["rejected_events"].empty()) {
    EXPECT_NE(text.find("rejected event (" + std::to_string(json["rejected_events"].size()) + ")"),
              std::string::npos);
  }
  EXPECT_NE(text.find("energy loss eta_k (1)"), std::string::npos);
  EXPECT_NE(text.find("time t (s)"), std::string::npos);
}

TEST_F(PlotsCli, AnalyzePlotOfAnHourScaleFileStaysSmall) {
  // The waveform is decimated to min/max per pixel column: the figure's size must not grow
  // with the recording. 7.4 s at 48 kHz is 354k samples; 1000 columns of 2 values plus markers
  // keep the SVG well under 1 MB (a plot of every sample would be ~20 MB).
  const auto svg = folder_ / "pingpong.svg";
  const auto run = RunBouncecal("analyze " + (SourceDir() / "samples/pingpong_hard.wav").string() +
                                " --plot " + svg.string());
  ASSERT_EQ(run.exit_status, 0) << run.output;
  EXPECT_LT(std::filesystem::file_size(svg), 1'000'000u);
}

TEST_F(PlotsCli, SimulateDropPlotsHeightWithImpactsAsPng) {
  const auto png = folder_ / "drop.png";
  const auto run = RunBouncecal("simulate drop --gamma 0.4 --quiet --plot " + png.string());
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const std::string bytes = ReadFileText(png);
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
}

TEST_F(PlotsCli, AWrongPlotExtensionNamesTheOptionAndTheAllowedEndings) {
  const auto run =
      RunBouncecal("simulate drop --gamma 0.4 --quiet --plot " + (folder_ / "drop.pdf").string());
  EXPECT_EQ(run.exit_status, 3) << run.output;
  EXPECT_NE(run.output.find("--plot"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(".png or .svg"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(folder_ / "drop.pdf"));
}

}  // namespace
}  // namespace bouncecal::testing
