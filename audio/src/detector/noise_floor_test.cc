#include "detector/noise_floor.h"

#include <gtest/gtest.h>

#include <random>
#include <span>
#include <vector>

namespace bouncecal::audio {
namespace {

// AddBlock must leave after every power exactly the floor that Add followed by power() leaves,
// whatever the block sizes, across several sub-window rotations (a sub-window here is 25
// frames: 0.2 s / 8 / 1 ms) and the first frame; exact, as the same operations run in the same
// order.
TEST(NoiseFloor, AddBlockGivesWhatSingleAddsGive) {
  std::mt19937 random(9);
  std::exponential_distribution<double> power(1e4);
  std::vector<double> stream(400);
  for (auto& x : stream) x = power(random);
  NoiseFloor singles(1e-3, 0.01, 0.2, 8), blocks(1e-3, 0.01, 0.2, 8);
  std::size_t at = 0;
  for (std::size_t size : {1u, 0u, 24u, 3u, 60u, 25u, 200u, 87u}) {
    std::vector<double> floors(size);
    blocks.AddBlock(std::span<const double>(stream).subspan(at, size), floors.data());
    for (std::size_t i = 0; i < size; ++i) {
      singles.Add(stream[at + i]);
      ASSERT_EQ(floors[i], singles.power()) << "frame " << at + i;
    }
    ASSERT_EQ(blocks.power(), singles.power());
    ASSERT_EQ(blocks.db(), singles.db());
    at += size;
  }
  ASSERT_EQ(at, stream.size());
}

}  // namespace
}  // namespace bouncecal::audio
