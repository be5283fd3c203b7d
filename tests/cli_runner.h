#ifndef BOUNCECAL_TESTS_CLI_RUNNER_H_
#define BOUNCECAL_TESTS_CLI_RUNNER_H_

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace bouncecal::testing {

struct CliResult {
  int exit_status = -1;
  std::string output;  // stdout and stderr together
};

// Runs the built bouncecal executable with the given argument string (shell-quoted by the
// caller) and captures what it prints. `environment` holds shell assignments for that run only
// (e.g. "SOURCE_DATE_EPOCH=0"), so the test process's own environment is never changed.
inline CliResult RunBouncecal(const std::string& arguments, const std::string& environment = "") {
  const std::string command =
      environment + " " + std::string(BOUNCECAL_EXECUTABLE) + " " + arguments + " 2>&1";
  CliResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t got = 0;
  while ((got = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), got);
  const int status = pclose(pipe);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline std::filesystem::path SharedDir() { return BOUNCECAL_SHARED_DIR; }
inline std::filesystem::path SourceDir() { return BOUNCECAL_SOURCE_DIR; }

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTS_CLI_RUNNER_H_
