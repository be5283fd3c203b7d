#include "bouncecal/testing/scratch_folder.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "bouncecal/testing/file_text.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

TEST(ScratchFolder, IsFreshAndNamedAfterTheProcess) {
  const ScratchFolder folder("a label");
  EXPECT_TRUE(fs::is_directory(folder.path()));
  EXPECT_TRUE(fs::is_empty(folder.path()));
  EXPECT_EQ(folder.path().parent_path(), fs::temp_directory_path());
  const std::string name = folder.path().filename().string();
  const std::string process = "bouncecal_" + std::to_string(::getpid()) + "_";
  EXPECT_EQ(name.rfind(process, 0), 0u) << name;
  EXPECT_EQ(name.substr(name.size() - 8), "_a_label") << name;
}

TEST(ScratchFolder, IsRemovedWithWhatItHolds) {
  fs::path path;
  {
    const ScratchFolder folder;
    path = folder.path();
    fs::create_directories(folder / "a" / "b");
    std::ofstream(folder / "a" / "b" / "c.txt") << "c";
  }
  EXPECT_FALSE(fs::exists(path));
}

TEST(ScratchFolder, StaysWhenAskedTo) {
  ASSERT_EQ(::setenv("BOUNCECAL_KEEP_TEST_FILES", "1", 1), 0);
  fs::path path;
  {
    const ScratchFolder folder;
    path = folder.path();
  }
  ::unsetenv("BOUNCECAL_KEEP_TEST_FILES");
  EXPECT_TRUE(fs::is_directory(path));
  fs::remove_all(path);
}

TEST(ScratchFolder, TwoOfOneTestAreTwoFolders) {
  const ScratchFolder first, second;
  EXPECT_NE(first.path(), second.path());
  EXPECT_TRUE(fs::is_directory(first.path()));
  EXPECT_TRUE(fs::is_directory(second.path()));
}

TEST(ScratchPath, PointsIntoTheTestsOwnFolderWithNothingThere) {
  const fs::path path = ScratchPath("result.json");
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_directory(path.parent_path()));
  EXPECT_EQ(ScratchPath("other.json").parent_path(), path.parent_path());
}

TEST(ScratchSubfolder, IsAnEmptyFolderInsideTheTestsFolder) {
  const fs::path folder = ScratchSubfolder("out");
  EXPECT_TRUE(fs::is_directory(folder));
  EXPECT_TRUE(fs::is_empty(folder));
  std::ofstream(folder / "x") << "x";
  EXPECT_TRUE(fs::is_empty(ScratchSubfolder("out")));
}

TEST(ReadFileText, ReturnsEveryByte) {
  const auto path = ScratchPath("bytes.bin");
  const std::string bytes("a\0b\r\n", 5);
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_EQ(ReadFileText(path), bytes);
  EXPECT_EQ(ReadFileText(ScratchPath("missing")), "");
  std::ofstream(ScratchPath("doc.json")) << R"({"a": [1, 2]})";
  EXPECT_EQ(ReadJsonFile(ScratchPath("doc.json"))["a"][1], 2);
}

}  // namespace
}  // namespace bouncecal::testing
