#include "bouncecal/calibrate/content_hash.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bouncecal/error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::calibrate {
namespace {

using bouncecal::testing::ScratchPath;

std::uint64_t HashOf(std::string_view text) {
  Fnv1a64 hash;
  hash.Update(text);
  return hash.digest();
}

TEST(Fnv1a64, MatchesThePublishedTestVectors) {
  // Test vectors from the FNV reference (isthe.com/chongo/tech/comp/fnv, test_fnv.c).
  EXPECT_EQ(HashOf(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(HashOf("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(HashOf("foobar"), 0x85944171f73967e8ULL);
}

TEST(Fnv1a64, ChunkingDoesNotChangeTheDigest) {
  Fnv1a64 chunked;
  chunked.Update("foo");
  chunked.Update("bar");
  EXPECT_EQ(chunked.digest(), HashOf("foobar"));
}

TEST(FileContentHash, HashesTheFileBytesAndNamesTheScheme) {
  const auto path = ScratchPath("content_hash_test.bin");
  {
    std::ofstream out(path, std::ios::binary);
    out << "foobar";
  }
  EXPECT_EQ(FileContentHash(path), "fnv1a64:85944171f73967e8");
}

TEST(FileContentHash, MissingFileIsAnInputError) {
  EXPECT_THROW(FileContentHash("/nonexistent/bouncecal/recording.wav"), InputError);
}

}  // namespace
}  // namespace bouncecal::calibrate
