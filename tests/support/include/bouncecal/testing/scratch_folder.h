#ifndef BOUNCECAL_TESTING_SCRATCH_FOLDER_H_
#define BOUNCECAL_TESTING_SCRATCH_FOLDER_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace bouncecal::testing {

// A fresh, empty folder for what one test writes, removed when the object goes:
// <temp>/bouncecal_<pid>_<n>[_<label>], the n-th of the process. The pid is there because ctest
// runs each test in its own process, two at a time: a folder of a fixed name was wiped by one
// process's SetUpTestSuite while another read it. The count keeps the folders of one process
// apart (a gtest executable run by hand runs all its tests in one). The test's name is not in it:
// the commands a test runs print their output paths, and a test that looks for a word in what
// they print ("warning") would find it in its own name. A folder of that name left by an earlier
// process is removed first; a label only helps a reader.
//
// The folder stays, and its path and test are printed, when its test failed (to read what the
// test wrote) or when BOUNCECAL_KEEP_TEST_FILES is set to anything but 0.
class ScratchFolder {
 public:
  explicit ScratchFolder(std::string_view label = "");
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string string() const { return path_.string(); }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
  // The test (or, in SetUpTestSuite, the suite) whose result decides whether the folder stays;
  // gtest owns both for the whole process.
  const ::testing::TestInfo* test_ = nullptr;
  const ::testing::TestSuite* suite_ = nullptr;
};

// `name` inside the running test's own ScratchFolder, for helpers that hand out paths where no
// fixture owns a folder. The folder is made at the test's first call and removed when a later test
// of the same process first calls, or when the process ends (kept as above).
std::filesystem::path ScratchPath(std::string_view name);

// ScratchPath(name) made an empty folder (anything at it before is removed first).
std::filesystem::path ScratchSubfolder(std::string_view name);

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTING_SCRATCH_FOLDER_H_
