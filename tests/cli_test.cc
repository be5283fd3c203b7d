#include <gtest/gtest.h>

#include <string>

#include "bouncecal/version.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

TEST(Cli, VersionPrintsTheProjectVersion) {
  const auto result = RunBouncecal("version");
  EXPECT_EQ(result.exit_status, 0);
  EXPECT_NE(result.output.find("bouncecal 0."), std::string::npos) << result.output;
}

TEST(Cli, VersionFlagPrintsTheSameLineAsTheVersionCommand) {
  const auto flag = RunBouncecal("--version");
  EXPECT_EQ(flag.exit_status, 0) << flag.output;
  EXPECT_EQ(flag.output, "bouncecal " + std::string(Version()) + "\n");
  EXPECT_EQ(flag.output, RunBouncecal("version").output);
}

TEST(Cli, UnknownSubcommandIsAUsageError) {
  const auto result = RunBouncecal("frobnicate");
  EXPECT_EQ(result.exit_status, 3) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
