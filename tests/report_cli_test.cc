// bouncecal report: one self-contained HTML page for a calibration, checked as text and, when
// Debian's chromium is installed, as rendered by a real browser.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bouncecal/calibrate/content_hash.h"
#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// The report of the shipped paper-style sample, made once for every test (a fit takes seconds).
class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new ScratchFolder();
    // The report reads recordings through calibrate::LoadSequences; an analyze --json file is
    // one of its inputs and keeps this test independent of recording support in that loader.
    const auto analysis =
        RunBouncecal("analyze " + (SourceDir() / "samples/steel_ball_h0.2m.wav").string() +
                     " --drop-height-m 0.2 --json " + Input().string());
    if (analysis.exit_status != 0) {
      run_ = new CliResult(analysis);
      return;
    }
    run_ = new CliResult(RunBouncecal("report " + Input().string() +
                                      " --drop-height-m 0.2 --ball steel-10mm -o " +
                                      (*folder_ / "report.html").string()));
  }
  static void TearDownTestSuite() {
    delete folder_;
    delete run_;
  }
  static std::filesystem::path Input() { return *folder_ / "steel_ball_h0.2m.json"; }
  static ScratchFolder* folder_;
  static CliResult* run_;
};
ScratchFolder* ReportCli::folder_ = nullptr;
CliResult* ReportCli::run_ = nullptr;

TEST_F(ReportCli, PageHasEverySectionTheFiguresAndTheInputHash) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  const std::string html = ReadFileText(*folder_ / "report.html");
  for (const char* id :
       {"inputs", "fit-summary", "analytic-check", "plots", "impacts", "material-card"}) {
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  }
  // The recording's waveform, the fit figure and the gamma-eta figure (walton-braun under
  // mean-energy-loss has the check).
  EXPECT_EQ(Count(html, "<svg"), 3u);
  EXPECT_NE(html.find(calibrate::FileContentHash(Input())), std::string::npos);
  EXPECT_NE(html.find("bouncecal-material/1"), std::string::npos);
  // The mean-energy-loss fit needs 3 impacts after the release: rows k = 1..3 at least.
  EXPECT_NE(html.find("<td class=\"text\">3</td>"), std::string::npos);
}

TEST_F(ReportCli, FittedDampingMatchesTheSamplesKnownEnergyLoss) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  const std::string html = ReadFileText(*folder_ / "report.html");
  // The card is shown escaped in a <pre>; its gamma_n is the fit.
  const std::string key = "&quot;gamma_n&quot;: ";
  const auto at = html.find(key);
  ASSERT_NE(at, std::string::npos);
  const double gamma_n = std::strtod(html.c_str() + at + key.size(), nullptr);
  // The shipped sample was synthesised with eta-bar = 0.58 exactly, so gamma_n = 0.58 / 1.42 =
  // 0.4085 (docs/physics.md). Tolerance 0.02: detected onsets carry ~10 us errors on 0.1-0.26 s
  // flights, i.e. ~0.01 in eta-bar over 3 impacts, and d gamma / d eta = (1 + gamma)^2 / 2 ~ 1.
  EXPECT_NEAR(gamma_n, 0.58 / 1.42, 0.02);
}

TEST_F(ReportCli, PageNeedsNoExternalResource) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  const std::string html = ReadFileText(*folder_ / "report.html");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  // gnuplot's SVG carries xlink:href only to its own #ids.
  for (auto at = html.find("href=\""); at != std::string::npos; at = html.find("href=\"", at + 1)) {
    EXPECT_EQ(html[at + 6], '#') << html.substr(at, 60);
  }
}

TEST_F(ReportCli, RendersInHeadlessChromium) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  std::string chromium;
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (std::filesystem::exists(candidate)) chromium = candidate;
  }
  if (chromium.empty()) {
    GTEST_SKIP() << "chromium is not installed (Debian package chromium; "
                    "scripts/install_deps.sh --tests installs it): the browser rendering check is "
                    "skipped";
  }
  std::string profile = (*folder_ / "profile-XXXXXX").string();
  ASSERT_NE(mkdtemp(profile.data()), nullptr);
  const auto page = *folder_ / "report.html";
  const auto screenshot = *folder_ / "report.png";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir=" +
      profile + " ";
  const auto dom = folder_->string() + "/dom.html";
  const std::string dump =
      chromium + flags + "--dump-dom file://" + page.string() + " > " + dom + " 2>/dev/null";
  ASSERT_EQ(std::system(dump.c_str()), 0);
  const std::string rendered = ReadFileText(dom);
  const std::string html = ReadFileText(page);
  // The DOM is what the browser parsed: sections, both figures and the fit values survive.
  EXPECT_NE(rendered.find("id=\"fit-summary\""), std::string::npos);
  EXPECT_NE(rendered.find("gamma_n fitted"), std::string::npos);
  EXPECT_EQ(Count(rendered, "<svg"), 3u);
  EXPECT_EQ(Count(rendered, "class=\"impact\""), Count(html, "class=\"impact\""));
  const std::string shot = chromium + flags +
                           "--window-size=1200,2400 --screenshot=" + screenshot.string() +
                           " file://" + page.string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(shot.c_str()), 0);
  // A blank page compresses to a few kB; tables, text and two figures take far more.
  EXPECT_GT(std::filesystem::file_size(screenshot), 50'000u);
  if (const char* keep = std::getenv("BOUNCECAL_KEEP_REPORT_SCREENSHOT")) {
    std::filesystem::copy_file(screenshot, keep, std::filesystem::copy_options::overwrite_existing);
  }
}

// The waveform's amplitude axis as the browser lays it out: 0 at the centre of the trace's band
// and plus and minus one 1-2-5 value (no "1.7e+02" peak digits), every label inside the figure
// and clear of the other labels and of the plot area. A script added to a copy of the page
// measures the rendered boxes; --dump-dom returns what it wrote into the page.
TEST_F(ReportCli, WaveformAmplitudeAxisIsReadableInHeadlessChromium) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  std::string chromium;
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (std::filesystem::exists(candidate)) chromium = candidate;
  }
  if (chromium.empty()) {
    GTEST_SKIP() << "chromium is not installed (Debian package chromium; "
                    "scripts/install_deps.sh --tests installs it)";
  }
  std::string html = ReadFileText(*folder_ / "report.html");
  const auto body_end = html.rfind("</body>");
  ASSERT_NE(body_end, std::string::npos);
  // Boxes in CSS pixels (the figure is drawn at 100 %): inside the <svg>, left of the plot area
  // and apart from each other, with half a pixel for rounding.
  html.insert(body_end, R"(<script>
const problems = [];
const labels = [];
for (const svg of document.querySelectorAll("svg.waveform-figure")) {
  const figure = svg.getBoundingClientRect();
  const plot = svg.querySelector(".plot-area").getBoundingClientRect();
  const boxes = [];
  for (const text of svg.querySelectorAll(".amplitude-axis text")) {
    const box = text.getBoundingClientRect();
    if (text.classList.contains("amplitude-tick")) labels.push(text.textContent);
    if (box.left < figure.left - 0.5 || box.right > figure.right + 0.5 ||
        box.top < figure.top - 0.5 || box.bottom > figure.bottom + 0.5) {
      problems.push("outside-the-figure:" + text.textContent);
    }
    if (box.right > plot.left + 0.5) problems.push("over-the-plot:" + text.textContent);
    for (const other of boxes) {
      if (box.left < other.right && other.left < box.right && box.top < other.bottom &&
          other.top < box.bottom) {
        problems.push("overlap:" + text.textContent);
      }
    }
    boxes.push(box);
  }
}
document.body.setAttribute("data-axis-check",
    "labels=" + labels.join(",") + ";problems=" + (problems.join(",") || "none"));
</script>
)");
  const auto page = *folder_ / "axis_check.html";
  std::ofstream(page) << html;
  std::string profile = (*folder_ / "profile-XXXXXX").string();
  ASSERT_NE(mkdtemp(profile.data()), nullptr);
  const auto dom = *folder_ / "axis_dom.html";
  const std::string dump = chromium +
                           " --headless --no-sandbox --disable-gpu --no-first-run "
                           "--disable-background-networking --disable-component-update "
                           "--window-size=1200,2400 --user-data-dir=" +
                           profile + " --dump-dom file://" + page.string() + " > " + dom.string() +
                           " 2>/dev/null";
  ASSERT_EQ(std::system(dump.c_str()), 0);
  const std::string rendered = ReadFileText(dom);
  const auto at = rendered.find("data-axis-check=\"");
  ASSERT_NE(at, std::string::npos) << "the check script did not run";
  const std::string check = rendered.substr(at + 17, rendered.find('"', at + 17) - at - 17);
  EXPECT_NE(check.find(";problems=none"), std::string::npos) << check;
  // Three ticks: +a, 0, -a, with a = 1, 2 or 5 times a power of ten, written plainly.
  const auto labels = check.substr(7, check.find(';') - 7);
  const auto first_comma = labels.find(',');
  ASSERT_NE(first_comma, std::string::npos) << check;
  const std::string top = labels.substr(0, first_comma);
  EXPECT_EQ(labels, top + ",0,-" + top) << check;
  EXPECT_EQ(top.find('e'), std::string::npos) << check;
  const double value = std::stod(top);
  const double mantissa = value / std::pow(10.0, std::floor(std::log10(value) + 1e-9));
  EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
              std::abs(mantissa - 5) < 1e-6)
      << top;
  // Drawn at its value: +a lies above the band's centre (y = 165) by half the band (75 px) times
  // a / peak, and a is at least 0.4 of the peak; 0 lies on the centre.
  const auto tick_at = [&](const std::string& text) {
    const auto mark = html.find("data-value=\"" + text + "\"");
    const auto y_at = html.find("y=\"", mark);
    return std::stod(html.substr(y_at + 3));
  };
  EXPECT_NEAR(tick_at("0"), 165, 0.05);
  const double above = 165 - tick_at(top);
  EXPECT_GE(above, 0.4 * 75 - 0.05);
  EXPECT_LE(above, 75 + 0.05);
  EXPECT_NEAR(tick_at("-" + top) - 165, above, 0.1);
}

// The waveform section draws every impact the analysis put in a sequence and every event it
// rejected, at its time, over the recording's decimated waveform.
TEST_F(ReportCli, WaveformMarksEveryImpactAndRejectedEventOfTheAnalysis) {
  ASSERT_EQ(run_->exit_status, 0) << run_->output;
  const std::string html = ReadFileText(*folder_ / "report.html");
  const auto analysis = nlohmann::json::parse(ReadFileText(Input()));
  const auto& recording = analysis["recordings"][0];
  std::vector<double> onsets;
  for (const auto& sequence : recording["sequences"]) {
    for (double onset : sequence["onsets_s"]) onsets.push_back(onset);
  }
  ASSERT_GE(onsets.size(), 4u);
  ASSERT_EQ(Count(html, "class=\"waveform-figure\""), 1u);
  EXPECT_EQ(Count(html, "class=\"impact\""), onsets.size());
  EXPECT_EQ(Count(html, "class=\"rejected\""), recording["rejected_events"].size());
  for (double onset : onsets) {
    char marker[64];
    std::snprintf(marker, sizeof marker, "class=\"impact\" data-time-s=\"%.9g\"", onset);
    EXPECT_NE(html.find(marker), std::string::npos) << marker;
  }
  // One stroke per pixel column of the 910 px plot area, and the loudest column lies at an
  // impact: x = 70 + 910 t / duration. Tolerance 3 columns (~5 ms here): the high-passed peak
  // follows the onset by the impact's rise and ring, about a millisecond.
  const auto path_at = html.find("class=\"waveform\" d=\"");
  ASSERT_NE(path_at, std::string::npos);
  const std::string path = html.substr(path_at, html.find('"', path_at + 22) - path_at);
  EXPECT_EQ(Count(path, "M"), 910u);
  double loudest_x = 0, loudest_span = -1;
  for (auto at = path.find('M'); at != std::string::npos; at = path.find('M', at + 1)) {
    char* end = nullptr;
    const double x = std::strtod(path.c_str() + at + 1, &end);
    const double top = std::strtod(end, &end);
    const double bottom = std::strtod(end + 1, nullptr);  // after the 'V'
    if (bottom - top > loudest_span) loudest_span = bottom - top, loudest_x = x;
  }
  const auto t1_at = html.find("data-t1-s=\"");
  ASSERT_NE(t1_at, std::string::npos);
  const double duration_s = std::strtod(html.c_str() + t1_at + 11, nullptr);
  double nearest_px = 1e9;
  for (double onset : onsets) {
    nearest_px = std::min(nearest_px, std::abs(70 + 910 * onset / duration_s - loudest_x));
  }
  EXPECT_LE(nearest_px, 3.0) << "loudest column at x = " << loudest_x;
}

TEST(ReportCliErrors, AnOutputThatIsNotHtmlNamesTheOption) {
  const auto run = RunBouncecal(
      "report " + (SourceDir() / "samples/steel_ball_h0.2m.wav").string() + " -o report.pdf");
  EXPECT_EQ(run.exit_status, 3) << run.output;
  EXPECT_NE(run.output.find("--output"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace bouncecal::testing
