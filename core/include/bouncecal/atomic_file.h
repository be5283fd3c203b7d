#ifndef BOUNCECAL_ATOMIC_FILE_H_
#define BOUNCECAL_ATOMIC_FILE_H_

#include <filesystem>
#include <fstream>
#include <string>

namespace bouncecal {

// Writes an output file so that readers never see it half-written: the content goes to a
// temporary name in the same folder and is renamed into place by Commit(). If the writer is
// destroyed without Commit() (an exception, an early return), the temporary file is removed and
// any existing file at the target path is left untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  std::ostream& stream() { return stream_; }
  const std::filesystem::path& temporary_path() const { return temporary_; }

  // Flushes, checks the stream and renames into place. Throws OutputError on failure.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Convenience: writes the whole text atomically.
void WriteFileAtomically(const std::filesystem::path& target, const std::string& content);

}  // namespace bouncecal

#endif  // BOUNCECAL_ATOMIC_FILE_H_
