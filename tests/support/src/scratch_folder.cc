#include "bouncecal/testing/scratch_folder.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>
#include <string>
#include <system_error>

namespace bouncecal::testing {
namespace {

// A label may hold any text: every character a file name might not take becomes '_'.
std::string FileNamePart(std::string_view text) {
  std::string part(text);
  for (char& c : part) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '_' || c == '-' || c == '.';
    if (!plain) c = '_';
  }
  return part;
}

bool KeepAsked() {
  const char* keep = std::getenv("BOUNCECAL_KEEP_TEST_FILES");
  return keep != nullptr && *keep != '\0' && std::string_view(keep) != "0";
}

// The folders whose owners are still alive. A process that ends in std::exit (a death test's
// child does) destroys no local object, only statics: this one then removes what they left.
class LiveFolders {
 public:
  ~LiveFolders() {
    if (KeepAsked()) return;
    std::error_code error;
    for (const auto& path : paths) std::filesystem::remove_all(path, error);
  }
  std::set<std::filesystem::path> paths;
};

LiveFolders& Live() {
  static LiveFolders live;
  return live;
}

}  // namespace

ScratchFolder::ScratchFolder(std::string_view label) {
  const auto* unit = ::testing::UnitTest::GetInstance();
  test_ = unit->current_test_info();
  suite_ = unit->current_test_suite();
  static int made = 0;  // gtest runs the tests of a process one after another
  // Joined part by part: GCC 12 misreads "_" + std::string as an overlapping copy (-Wrestrict).
  std::string name = "bouncecal_";
  name.append(std::to_string(::getpid())).append("_").append(std::to_string(++made));
  if (!label.empty()) name.append("_").append(FileNamePart(label));
  path_ = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
  Live().paths.insert(path_);
}

ScratchFolder::~ScratchFolder() {
  Live().paths.erase(path_);
  const bool failed =
      test_ != nullptr ? test_->result()->Failed() : suite_ != nullptr && suite_->Failed();
  if (failed || KeepAsked()) {
    const std::string owner = test_ != nullptr
                                  ? std::string(test_->test_suite_name()) + "." + test_->name()
                              : suite_ != nullptr ? suite_->name()
                                                  : "no test";
    std::fprintf(stderr, "kept %s (%s)\n", path_.c_str(), owner.c_str());
    return;
  }
  std::error_code error;  // a destructor must not throw; a folder left behind is harmless
  std::filesystem::remove_all(path_, error);
}

std::filesystem::path ScratchPath(std::string_view name) {
  // One folder at a time: the running test's. A static, so the last one goes at exit; made on the
  // first call (not constant-initialised), so it goes before gtest's UnitTest, which it asks
  // whether its test failed.
  struct Current {
    // Statics die in the reverse order of their construction: the registry of live folders must
    // be made first, so that it is still there when this one's folder is removed at exit.
    Current() { Live(); }
    std::unique_ptr<ScratchFolder> folder;
    const ::testing::TestInfo* owner = nullptr;
  };
  static Current current;
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  if (current.folder == nullptr || test != current.owner) {
    current.folder.reset();  // the earlier test's, before the new one is made
    current.folder = std::make_unique<ScratchFolder>();
    current.owner = test;
  }
  return *current.folder / name;
}

std::filesystem::path ScratchSubfolder(std::string_view name) {
  const auto folder = ScratchPath(name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

}  // namespace bouncecal::testing
