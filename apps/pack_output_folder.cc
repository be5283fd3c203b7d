#include "pack_output_folder.h"

#include <fmt/core.h>
#include <signal.h>

#include <cerrno>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/error.h"
#include "output_target.h"

namespace bouncecal::apps {
namespace {

// Throws OutputError unless the temporary that the real write of `target` starts with can be
// created (it is removed again at once). Trying is the sure test: access() says yes to root in
// folders such as /proc where no file can be made.
void ProbeWritable(const std::filesystem::path& target) { AtomicFile probe(target); }

// The files pack writes into its output folder (WritePackTables, WritePackSummaryJson,
// PlotPacking, the checkpoint and the dumps named dump.<step>.lammpstrj).
bool IsPackOutputName(const std::string& name) {
  for (const char* own :
       {"history.csv", "profile.csv", "coordination.csv", "particles.csv", "summary.json",
        "profile.png", "history.png", "plots.gp", kCheckpointName}) {
    if (name == own) return true;
  }
  const std::string_view prefix = "dump.";
  const std::string_view suffix = ".lammpstrj";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  const std::string step = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return step.find_first_not_of("0123456789") == std::string::npos;
}

// A temporary "<own output>.tmp.<pid>" (AtomicFile's name) whose process no longer runs: left by
// a run killed while writing (SIGKILL, a second SIGINT, a crash). Those of a live process,
// another run writing into the same folder right now, are left alone.
bool IsStaleTemporary(const std::string& name) {
  const auto mark = name.rfind(".tmp.");
  if (mark == std::string::npos || !IsPackOutputName(name.substr(0, mark))) return false;
  const std::string pid_text = name.substr(mark + 5);
  if (pid_text.empty() || pid_text.size() > 9 ||
      pid_text.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  const auto pid = static_cast<pid_t>(std::stol(pid_text));
  return pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH;
}

}  // namespace

std::filesystem::path FirstMissingFolder(const std::filesystem::path& dir) {
  std::filesystem::path missing;
  std::error_code error;
  for (auto p = std::filesystem::absolute(dir, error); !p.empty() && !error; p = p.parent_path()) {
    if (std::filesystem::exists(p, error)) break;
    missing = p;
    if (p == p.parent_path()) break;
  }
  return missing;
}

void CheckOutputsWritable(const std::filesystem::path& dir, const std::filesystem::path& json) {
  try {
    ProbeWritable(dir / "summary.json");
  } catch (const OutputError&) {
    throw OutputError(
        fmt::format("cannot create files in the output folder {}; make it writable or pass -o DIR",
                    dir.string()));
  }
  if (json.empty() || IsStdout(json)) return;
  const std::filesystem::path& path = json;
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw OutputError(
        fmt::format("--json {}: is a folder; give the path of a file to write", json.string()));
  }
  if (!std::filesystem::is_directory(folder, error)) {
    throw OutputError(fmt::format(
        "--json {}: {} is not an existing folder; create it or choose a path in an existing "
        "folder",
        json.string(), folder.string()));
  }
  try {
    ProbeWritable(path);
  } catch (const OutputError&) {
    throw OutputError(fmt::format(
        "--json {}: cannot create a file in {}; make it writable or choose another path",
        json.string(), folder.string()));
  }
}

void RemoveEarlierOutputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> earlier;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    std::error_code kind_error;
    if (!entry.is_directory(kind_error) && IsPackOutputName(entry.path().filename().string())) {
      earlier.push_back(entry.path());
    }
  }
  for (const auto& path : earlier) {
    std::filesystem::remove(path, error);
    if (error) {
      throw OutputError(fmt::format(
          "cannot remove {} of an earlier run ({}); remove it by hand or pass another -o DIR",
          path.string(), error.message()));
    }
  }
}

void RemoveStaleTemporaries(const std::filesystem::path& dir) {
  std::error_code error;
  std::vector<std::filesystem::path> stale;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    std::error_code kind_error;
    if (entry.is_regular_file(kind_error) && IsStaleTemporary(entry.path().filename().string())) {
      stale.push_back(entry.path());
    }
  }
  for (const auto& path : stale) {
    std::filesystem::remove(path, error);
    if (error) {
      throw OutputError(fmt::format(
          "cannot remove {}, left by a run that was killed ({}); remove it by hand or pass "
          "another --out DIR",
          path.string(), error.message()));
    }
  }
}

std::string ReadCheckpoint(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(
        fmt::format("--resume {}: is a folder; give the checkpoint file ({} in the "
                    "output folder of the run to continue)",
                    path, kCheckpointName));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(fmt::format(
        "--resume {}: cannot be read; give the checkpoint file ({} in the output folder of the "
        "run to continue)",
        path, kCheckpointName));
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(fmt::format("--resume {}: reading it failed", path));
  return bytes;
}

}  // namespace bouncecal::apps
