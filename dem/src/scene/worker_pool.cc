#include "scene/worker_pool.h"

namespace bouncecal::dem::scene {
namespace {

// About 5-10 us of polling before sleeping: long enough to catch the next loop of the same
// step without a system call, short enough to give the core away on a busy machine.
constexpr int kSpinIterations = 200;
constexpr std::int64_t kMinItemsPerThread = 512;

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

WorkerPool::WorkerPool(int threads) {
  for (int chunk = 1; chunk < threads; ++chunk) {
    workers_.emplace_back([this] { WorkerLoop(); });
  }
}

WorkerPool::~WorkerPool() {
  stop_.store(true, std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_acq_rel);
  generation_.notify_all();
  for (auto& worker : workers_) worker.join();
}

void WorkerPool::RunChunk(int chunk) {
  const std::int64_t count = threads();
  const std::int64_t begin = n_ * chunk / count;
  const std::int64_t end = n_ * (chunk + 1) / count;
  if (end > begin) (*body_)(chunk, begin, end);
}

void WorkerPool::RunClaimedChunks(std::uint64_t generation) {
  const int chunks = threads();
  std::uint64_t claim = claim_.load(std::memory_order_acquire);
  for (;;) {
    if ((claim >> 16) != generation || static_cast<int>(claim & 0xffff) >= chunks) return;
    if (claim_.compare_exchange_weak(claim, claim + 1, std::memory_order_acq_rel)) {
      RunChunk(static_cast<int>(claim & 0xffff));
      if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) done_.notify_all();
      claim = claim_.load(std::memory_order_acquire);
    }
  }
}

void WorkerPool::ParallelFor(std::int64_t n,
                             const std::function<void(int, std::int64_t, std::int64_t)>& body) {
  // Small loops run on the caller: waking a sleeping worker costs microseconds on an idle
  // machine and a scheduler slice (milliseconds) on a busy one. The split never changes results.
  if (workers_.empty() || n < kMinItemsPerThread * threads()) {
    if (n > 0) body(0, 0, n);
    return;
  }
  body_ = &body;
  n_ = n;
  done_.store(0, std::memory_order_relaxed);
  const std::uint64_t generation = generation_.load(std::memory_order_relaxed) + 1;
  claim_.store(generation << 16, std::memory_order_release);  // publishes body_, n_ and done_
  generation_.store(generation, std::memory_order_release);
  generation_.notify_all();
  RunClaimedChunks(generation);
  // Only chunks a worker is running are left: wait for them.
  const int chunks = threads();
  int spins = 0;
  for (int done = done_.load(std::memory_order_acquire); done != chunks;
       done = done_.load(std::memory_order_acquire)) {
    if (++spins < kSpinIterations) {
      CpuRelax();
    } else {
      done_.wait(done, std::memory_order_acquire);
    }
  }
}

void WorkerPool::WorkerLoop() {
  std::uint64_t seen = 0;
  for (;;) {
    int spins = 0;
    std::uint64_t now = generation_.load(std::memory_order_acquire);
    while (now == seen) {
      if (++spins < kSpinIterations) {
        CpuRelax();
      } else {
        generation_.wait(seen, std::memory_order_acquire);
      }
      now = generation_.load(std::memory_order_acquire);
    }
    seen = now;
    if (stop_.load(std::memory_order_acquire)) return;
    RunClaimedChunks(now);
  }
}

}  // namespace bouncecal::dem::scene
