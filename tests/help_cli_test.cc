// Every subcommand's --help shows an example, found by walking the command tree the executable
// itself reports, so a subcommand added later is covered without editing this test.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

// Names listed under "Subcommands:" in CLI11's help text.
std::vector<std::string> Subcommands(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream in(help);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Subcommands:", 0) == 0 || line.rfind("SUBCOMMANDS:", 0) == 0) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line.empty() || line[0] != ' ') break;
    // A name sits at the start of its row, indented by two spaces; deeper-indented rows continue
    // a long description and must not be walked as commands (that recursed without end).
    if (line.size() < 3 || line[2] == ' ') continue;
    std::istringstream words(line);
    std::string name;
    words >> name;
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

void CheckTree(const std::string& path, std::vector<std::string>& checked) {
  const auto run = RunBouncecal(path + " --help");
  ASSERT_EQ(run.exit_status, 0) << path << ": " << run.output;
  const auto children = Subcommands(run.output);
  if (!path.empty() && children.empty()) {
    checked.push_back(path);
    EXPECT_NE(run.output.find("Example"), std::string::npos)
        << "bouncecal " << path << " --help shows no example:\n"
        << run.output;
  }
  for (const auto& child : children) CheckTree(path.empty() ? child : path + " " + child, checked);
}

TEST(HelpCli, EverySubcommandHelpShowsAnExample) {
  std::vector<std::string> checked;
  CheckTree("", checked);
  // The tree has at least the commands of issues 1-6; fewer means the help parsing broke.
  EXPECT_GE(checked.size(), 10u);
  for (const char* expected : {"analyze", "calibrate", "report", "simulate drop", "export"}) {
    EXPECT_NE(std::find(checked.begin(), checked.end(), expected), checked.end()) << expected;
  }
}

TEST(HelpCli, BadOptionValuesNameTheOptionAndItsRangeWithExitStatus3) {
  struct Case {
    const char* arguments;
    const char* option;  // must appear in the message
    const char* range;   // the valid range, as the message states it
  };
  // The input file need not exist: option values are checked before any file is read.
  const Case cases[] = {
      {"calibrate missing.json --confidence 2", "--confidence", "(0, 1)"},
      {"calibrate missing.json --drop-height-m 0.2 --drop-height-uncertainty-m -1",
       "--drop-height-uncertainty-m", ">= 0"},
      {"calibrate missing.json --first 0", "--first", "at least 1"},
      {"report missing.json --threads 0 -o r.html", "--threads", ">= 1"},
      {"sweep --values 0.1:0.9:0", "--values", "0 < step"},
      {"analyze missing.wav --first 0", "--first", "at least 1"},
      {"simulate drop --plot drop.pdf", "--plot", ".png or .svg"},
  };
  for (const auto& c : cases) {
    const auto run = RunBouncecal(c.arguments);
    EXPECT_EQ(run.exit_status, 3) << c.arguments << ": " << run.output;
    EXPECT_NE(run.output.find(c.option), std::string::npos) << c.arguments << ": " << run.output;
    EXPECT_NE(run.output.find(c.range), std::string::npos) << c.arguments << ": " << run.output;
  }
}

}  // namespace
}  // namespace bouncecal::testing
