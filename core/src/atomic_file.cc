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

AtomicFile::AtomicFile(std::filesystem::path target)
    : target_(std::move(target)), temporary_(TemporaryNameFor(target_)) {
  if (std::filesystem::is_directory(target_)) {
    throw OutputError(target_.string() + ": is a directory; give a file name for the output");
  }
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) {
    throw OutputError(target_.string() +
                      ": cannot create the output file; check that the folder exists and is "
                      "writable");
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    stream_.close();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFile::Commit() {
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || stream_.fail()) {
    throw OutputError(target_.string() +
                      ": writing the output failed (disk full?); nothing was "
                      "written");
  }
  std::error_code error;
  std::filesystem::rename(temporary_, target_, error);
  if (error) {
    throw OutputError(target_.string() +
                      ": cannot move the finished output into place: " + error.message());
  }
  committed_ = true;
}

void WriteFileAtomically(const std::filesystem::path& target, const std::string& content) {
  AtomicFile file(target);
  file.stream() << content;
  file.Commit();
}

}  // namespace bouncecal
