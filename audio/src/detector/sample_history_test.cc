#include "detector/sample_history.h"

#include <gtest/gtest.h>

#include <vector>

namespace bouncecal::audio {
namespace {

// PushBlock must hold exactly what pushing the samples one by one holds, whatever the block
// sizes: blocks that wrap the ring, exactly fill it, or are longer than it. Exact comparison:
// samples are copied, never computed.
TEST(SampleHistory, PushBlockHoldsWhatSinglePushesHold) {
  SampleHistory<float> blocks(16);
  SampleHistory<float> singles(16);
  float next = 0;
  for (std::size_t size : {3u, 16u, 5u, 40u, 1u, 0u, 15u, 17u, 9u}) {
    std::vector<float> block(size);
    for (auto& x : block) x = next++;
    blocks.PushBlock(block);
    for (float x : block) singles.Push(x);
    ASSERT_EQ(blocks.end(), singles.end());
    ASSERT_EQ(blocks.begin(), singles.begin());
    for (std::int64_t i = blocks.begin(); i < blocks.end(); ++i) {
      ASSERT_EQ(blocks[i], singles[i]) << "index " << i << " after a block of " << size;
      ASSERT_EQ(blocks[i], static_cast<float>(i));
    }
  }
}

// Contiguous views stop at the ring's wrap and never beyond the count asked for; reading runs
// view by view gives every held sample once, in order.
TEST(SampleHistory, ContiguousViewsSplitOnlyWhereTheRingWraps) {
  SampleHistory<float> history(16);
  for (int i = 0; i < 37; ++i) history.Push(static_cast<float>(i));
  // Held: 21..36, stored from slot 5 (21 & 15) to the end and on from slot 0.
  EXPECT_EQ(history.Contiguous(21, 16).size(), 11u);
  EXPECT_EQ(history.Contiguous(21, 4).size(), 4u);
  EXPECT_EQ(history.Contiguous(32, 5).size(), 5u);
  std::vector<float> read;
  for (std::int64_t at = history.begin(); at < history.end();) {
    const auto view = history.Contiguous(at, static_cast<std::size_t>(history.end() - at));
    ASSERT_FALSE(view.empty());
    read.insert(read.end(), view.begin(), view.end());
    at += static_cast<std::int64_t>(view.size());
  }
  ASSERT_EQ(read.size(), 16u);
  for (std::size_t i = 0; i < read.size(); ++i) EXPECT_EQ(read[i], static_cast<float>(21 + i));
}

}  // namespace
}  // namespace bouncecal::audio
