#include "sample_history.h"

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

}  // namespace
}  // namespace bouncecal::audio
