#include "scene/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <vector>

namespace bouncecal::dem::scene {
namespace {

// Every index of every loop is visited exactly once, by the chunk that owns it, for thread counts
// below, at and above the machine's cores (a pool larger than the machine must still finish:
// the caller runs the chunks of workers that have no core).
TEST(WorkerPool, EveryChunkRunsExactlyOnceInEveryLoop) {
  for (int threads : {1, 2, 3, 5}) {
    WorkerPool pool(threads);
    const std::int64_t n = 10000;  // above the bound under which a loop runs on the caller alone
    std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
    std::vector<std::int64_t> chunk_begin(static_cast<std::size_t>(pool.chunks()), -1);
    for (int loop = 0; loop < 200; ++loop) {
      pool.ParallelFor(n, [&](int chunk, std::int64_t begin, std::int64_t end) {
        // A chunk is a fixed range: the same in every loop whichever thread runs it.
        const auto c = static_cast<std::size_t>(chunk);
        if (loop == 0) chunk_begin[c] = begin;
        EXPECT_EQ(chunk_begin[c], begin) << "threads " << threads << " chunk " << chunk;
        EXPECT_EQ(end, n * (chunk + 1) / pool.chunks());
        for (std::int64_t i = begin; i < end; ++i) {
          visits[static_cast<std::size_t>(i)].fetch_add(1, std::memory_order_relaxed);
        }
      });
      // ParallelFor returns only after every chunk is done: all counts are complete here.
      for (std::int64_t i = 0; i < n; i += 997) {
        ASSERT_EQ(visits[static_cast<std::size_t>(i)].load(), loop + 1)
            << "threads " << threads << " loop " << loop << " index " << i;
      }
    }
    for (const auto& v : visits) ASSERT_EQ(v.load(), 200);
  }
}

TEST(WorkerPool, SmallLoopsRunOnTheCallerAsOneChunk) {
  WorkerPool pool(2);
  int calls = 0;
  pool.ParallelFor(100, [&](int chunk, std::int64_t begin, std::int64_t end) {
    ++calls;  // not atomic on purpose: a second thread here would be a data race (TSan, ASan)
    EXPECT_EQ(chunk, 0);
    EXPECT_EQ(begin, 0);
    EXPECT_EQ(end, 100);
  });
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace bouncecal::dem::scene
