#include "bouncecal/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "bouncecal/error.h"
#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal {
namespace {

using bouncecal::testing::ReadFileText;
using bouncecal::testing::ScratchSubfolder;

TEST(AtomicFile, CommitPutsContentInPlaceAndLeavesNoTemporary) {
  const auto dir = ScratchSubfolder("commit");
  WriteFileAtomically(dir / "out.json", "{}\n");
  EXPECT_EQ(ReadFileText(dir / "out.json"), "{}\n");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicFile, AbandonedWriteLeavesExistingFileUntouched) {
  const auto dir = ScratchSubfolder("abandon");
  WriteFileAtomically(dir / "out.json", "old");
  try {
    AtomicFile file(dir / "out.json");
    file.stream() << "new, half written";
    throw std::runtime_error("simulated failure before commit");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(ReadFileText(dir / "out.json"), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicFile, MissingFolderIsAnOutputError) {
  EXPECT_THROW(AtomicFile("/nonexistent-bouncecal-dir/out.json"), OutputError);
}

TEST(AtomicPath, CommitRenamesTheTemporaryAndAbandonRemovesIt) {
  const auto dir = ScratchSubfolder("path");
  {
    AtomicPath path(dir / "out.wav");
    EXPECT_EQ(path.temporary_path().parent_path(), dir);
    std::ofstream(path.temporary_path()) << "audio";
    path.Commit();
  }
  EXPECT_EQ(ReadFileText(dir / "out.wav"), "audio");
  {
    AtomicPath path(dir / "out.wav");
    std::ofstream(path.temporary_path()) << "half";
  }
  EXPECT_EQ(ReadFileText(dir / "out.wav"), "audio");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicPath, MissingFolderOrDirectoryTargetIsAnOutputError) {
  EXPECT_THROW(AtomicPath("/nonexistent-bouncecal-dir/out.wav"), OutputError);
  EXPECT_THROW(AtomicPath(std::filesystem::temp_directory_path()), OutputError);
}

}  // namespace
}  // namespace bouncecal
