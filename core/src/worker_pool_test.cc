#include "bouncecal/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace bouncecal {
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

// Calibration's use: a handful of long items (one fit per law), each run once, whatever their
// number against the threads and chunks.
TEST(WorkerPool, ForEachRunsEveryItemExactlyOnce) {
  for (int threads : {1, 2, 3}) {
    WorkerPool pool(threads);
    for (std::int64_t n : {0, 1, 2, 3, 5, 17, 100}) {
      std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
      pool.ParallelForEach(n, [&](std::int64_t i) {
        runs[static_cast<std::size_t>(i)].fetch_add(1, std::memory_order_relaxed);
      });
      for (std::int64_t i = 0; i < n; ++i) {
        EXPECT_EQ(runs[static_cast<std::size_t>(i)].load(), 1)
            << "threads " << threads << " items " << n << " item " << i;
      }
    }
  }
}

// Two items on two threads run at the same time, where ParallelFor would run a loop this small
// on the caller alone: each waits (up to 30 s, far beyond any scheduling delay) until the other
// has started. Run one after the other, the first would wait out the 30 s and find itself alone.
TEST(WorkerPool, ForEachRunsFewItemsConcurrently) {
  WorkerPool pool(2);
  std::mutex mutex;
  std::condition_variable started;
  int running = 0;
  std::vector<bool> met(2, false);
  pool.ParallelForEach(2, [&](std::int64_t i) {
    std::unique_lock lock(mutex);
    ++running;
    started.notify_all();
    met[static_cast<std::size_t>(i)] =
        started.wait_for(lock, std::chrono::seconds(30), [&] { return running == 2; });
  });
  EXPECT_TRUE(met[0]);
  EXPECT_TRUE(met[1]);
}

}  // namespace
}  // namespace bouncecal
