#ifndef BOUNCECAL_ATOMIC_FILE_H_
#define BOUNCECAL_ATOMIC_FILE_H_

#include <filesystem>
#include <fstream>
#include <string>

namespace bouncecal {

// The path half of an atomic write, for writers that hand a file name to a C library (libsndfile)
// instead of writing to a stream: write to temporary_path(), then Commit() renames it onto the
// target. Destroyed without Commit(), it removes the temporary and leaves the target untouched.
class AtomicPath {
 public:
  // Throws OutputError when the target is a directory or its folder does not exist.
  explicit AtomicPath(std::filesystem::path target);
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;
  ~AtomicPath();

  const std::filesystem::path& target_path() const { return target_; }
  const std::filesystem::path& temporary_path() const { return temporary_; }

  // Renames the finished temporary into place. Throws OutputError on failure.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  bool committed_ = false;
};

// Writes an output file so that readers never see it half-written: the content goes to a
// temporary name in the same folder and is renamed into place by Commit(). If the writer is
// destroyed without Commit() (an exception, an early return), the temporary file is removed and
// any existing file at the target path is left untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::filesystem::path& temporary_path() const { return path_.temporary_path(); }

  // Flushes, checks the stream and renames into place. Throws OutputError on failure.
  void Commit();

 private:
  AtomicPath path_;  // declared first: destroyed after the stream has closed the file
  std::ofstream stream_;
};

// Convenience: writes the whole text atomically.
void WriteFileAtomically(const std::filesystem::path& target, const std::string& content);

}  // namespace bouncecal

#endif  // BOUNCECAL_ATOMIC_FILE_H_
