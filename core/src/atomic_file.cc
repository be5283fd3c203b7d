#include "bouncecal/atomic_file.h"

#include <unistd.h>

#include <system_error>

#include "bouncecal/error.h"

namespace bouncecal {
namespace {

std::filesystem::path TemporaryNameFor(const std::filesystem::path& target) {
  // The pid keeps two concurrent runs writing the same target from clobbering each other's
  // temporary; staying in the target's folder keeps the final rename atomic (same filesystem).
  std::filesystem::path temporary = target;
  temporary += ".tmp." + std::to_string(::getpid());
  return temporary;
}

}  // namespace

AtomicPath::AtomicPath(std::filesystem::path target)
    : target_(std::move(target)), temporary_(TemporaryNameFor(target_)) {
  std::error_code ignored;
  if (std::filesystem::is_directory(target_, ignored)) {
    throw OutputError(target_.string() + ": is a directory; give a file name for the output");
  }
  const std::filesystem::path folder =
      target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(folder, ignored)) {
    throw OutputError(target_.string() + ": cannot create the output file; the folder " +
                      folder.string() + " does not exist");
  }
}

AtomicPath::~AtomicPath() {
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicPath::Commit() {
  std::error_code error;
  std::filesystem::rename(temporary_, target_, error);
  if (error) {
    throw OutputError(target_.string() +
                      ": cannot move the finished output into place: " + error.message());
  }
  committed_ = true;
}

AtomicFile::AtomicFile(std::filesystem::path target) : path_(std::move(target)) {
  stream_.open(path_.temporary_path(), std::ios::binary | std::ios::trunc);
  if (!stream_) {
    throw OutputError(path_.target_path().string() +
                      ": cannot create the output file; check that the folder exists and is "
                      "writable");
  }
}

void AtomicFile::Commit() {
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || stream_.fail()) {
    throw OutputError(path_.target_path().string() +
                      ": writing the output failed (disk full?); nothing was "
                      "written");
  }
  path_.Commit();
}

void WriteFileAtomically(const std::filesystem::path& target, const std::string& content) {
  AtomicFile file(target);
  file.stream() << content;
  file.Commit();
}

}  // namespace bouncecal
