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

// AddBlocks runs floors in step side by side, and floors out of step one after the other:
// either way every floor leaves after every power exactly what Add leaves. Three fresh floors
// of different smoothing in step, over blocks that cross sub-window rotations and the first
// frame; then two of them, one a frame ahead of the other.
TEST(NoiseFloor, AddBlocksGivesWhatSingleAddsGiveInStepOrNot) {
  std::mt19937 random(10);
  std::exponential_distribution<double> power(1e4);
  std::vector<std::vector<double>> streams(3, std::vector<double>(500));
  for (auto& stream : streams) {
    for (auto& x : stream) x = power(random);
  }
  std::vector<NoiseFloor> singles, blocks;
  for (double smoothing_s : {0.01, 0.003, 0.02}) {
    singles.emplace_back(1e-3, smoothing_s, 0.2, 8);
    blocks.emplace_back(1e-3, smoothing_s, 0.2, 8);
  }
  std::vector<std::size_t> at(3, 0);
  const auto add_blocks = [&](const std::vector<std::size_t>& floors, std::size_t size) {
    std::vector<NoiseFloor*> these;
    std::vector<std::span<const double>> powers;
    std::vector<std::vector<double>> out(floors.size(), std::vector<double>(size));
    std::vector<double*> out_pointers;
    for (std::size_t i = 0; i < floors.size(); ++i) {
      these.push_back(&blocks[floors[i]]);
      powers.push_back(std::span<const double>(streams[floors[i]]).subspan(at[floors[i]], size));
      out_pointers.push_back(out[i].data());
    }
    NoiseFloor::AddBlocks(these, powers, out_pointers);
    for (std::size_t i = 0; i < floors.size(); ++i) {
      const std::size_t f = floors[i];
      for (std::size_t k = 0; k < size; ++k) {
        singles[f].Add(streams[f][at[f] + k]);
        ASSERT_EQ(out[i][k], singles[f].power()) << "floor " << f << " frame " << at[f] + k;
      }
      at[f] += size;
    }
  };
  for (std::size_t size : {1u, 0u, 24u, 3u, 60u, 25u, 87u}) add_blocks({0, 1, 2}, size);
  add_blocks({2}, 1);
  for (std::size_t size : {1u, 24u, 60u, 25u, 87u}) add_blocks({1, 2}, size);
}

}  // namespace
}  // namespace bouncecal::audio
