#include "bouncecal/worker_pool.h"

#include <chrono>

namespace bouncecal {
namespace {

// Polling budget before sleeping on the futex. A step of a few thousand particles is
// ~100-300 us and its serial part (neighbour rebuild, first-contact stop) up to ~1 ms, while a
// futex wake-up costs tens of microseconds in a VM: with ~5-10 us of polling (200 pauses) a
// 2-thread run spent much of its CPU sleeping and waking. Polling for up to kSpinBudget
// catches the next loop of the same or the next step without a system call; on a busy machine
// a waiter still gives its core away after that long, a small fraction of a scheduler slice.
constexpr auto kSpinBudget = std::chrono::microseconds(100);
// The clock is read once per this many pauses (~1-2 us), so polling does not hammer it.
constexpr int kPausesPerClockRead = 32;
constexpr std::int64_t kMinItemsPerThread = 512;

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Polls until `value` differs from `old` for up to kSpinBudget, then sleeps until it does.
template <typename T>
T WaitForChange(const std::atomic<T>& value, T old) {
  T now = value.load(std::memory_order_acquire);
  if (now != old) return now;
  const auto deadline = std::chrono::steady_clock::now() + kSpinBudget;
  for (;;) {
    for (int i = 0; i < kPausesPerClockRead; ++i) {
      CpuRelax();
      now = value.load(std::memory_order_acquire);
      if (now != old) return now;
    }
    if (std::chrono::steady_clock::now() >= deadline) break;
  }
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    now = value.load(std::memory_order_acquire);
    if (now != old) return now;
  }
}

}  // namespace

WorkerPool::WorkerPool(int threads)
    : claims_(static_cast<std::size_t>(threads > 1 ? threads * kChunksPerThread : 1)) {
  for (int thread = 1; thread < threads; ++thread) {
    workers_.emplace_back([this, thread] { WorkerLoop(thread); });
  }
}

WorkerPool::~WorkerPool() {
  stop_.store(true, std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_acq_rel);
  generation_.notify_all();
  for (auto& worker : workers_) worker.join();
}

void WorkerPool::RunChunk(int chunk) {
  const std::int64_t count = chunks();
  const std::int64_t begin = n_ * chunk / count;
  const std::int64_t end = n_ * (chunk + 1) / count;
  if (end > begin) (*body_)(chunk, begin, end);
}

bool WorkerPool::Claim(int chunk, std::uint64_t generation) {
  auto& claim = claims_[static_cast<std::size_t>(chunk)];
  std::uint64_t open = 2 * generation;
  if (claim.load(std::memory_order_relaxed) != open) return false;
  return claim.compare_exchange_strong(open, open + 1, std::memory_order_acq_rel);
}

void WorkerPool::RunClaimedChunks(int thread, std::uint64_t generation) {
  const int chunks = this->chunks();
  auto run = [&](int chunk) {
    if (!Claim(chunk, generation)) return;
    RunChunk(chunk);
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) done_.notify_all();
  };
  const int home = thread * kChunksPerThread;
  for (int c = home; c < home + kChunksPerThread; ++c) run(c);
  // Then the others' leftovers, each thread's from its far end, where its owner gets last.
  for (int t = 1; t < threads(); ++t) {
    const int other = ((thread + t) % threads()) * kChunksPerThread;
    for (int c = other + kChunksPerThread - 1; c >= other; --c) run(c);
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
  RunOnAllThreads(n, body);
}

void WorkerPool::ParallelForEach(std::int64_t n, const std::function<void(std::int64_t)>& body) {
  const std::function<void(int, std::int64_t, std::int64_t)> items =
      [&body](int, std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) body(i);
      };
  if (workers_.empty() || n < 2) {
    if (n > 0) items(0, 0, n);
    return;
  }
  RunOnAllThreads(n, items);
}

void WorkerPool::RunOnAllThreads(std::int64_t n,
                                 const std::function<void(int, std::int64_t, std::int64_t)>& body) {
  body_ = &body;
  n_ = n;
  done_.store(0, std::memory_order_relaxed);
  const std::uint64_t generation = generation_.load(std::memory_order_relaxed) + 1;
  for (auto& claim : claims_) {
    claim.store(2 * generation, std::memory_order_release);  // publishes body_, n_ and done_
  }
  generation_.store(generation, std::memory_order_release);
  generation_.notify_all();
  RunClaimedChunks(0, generation);
  // Only chunks a worker is running are left: wait for them.
  const int chunks = this->chunks();
  for (int done = done_.load(std::memory_order_acquire); done != chunks;) {
    done = WaitForChange(done_, done);
  }
}

void WorkerPool::WorkerLoop(int thread) {
  std::uint64_t seen = 0;
  for (;;) {
    const std::uint64_t now = WaitForChange(generation_, seen);
    seen = now;
    if (stop_.load(std::memory_order_acquire)) return;
    RunClaimedChunks(thread, now);
  }
}

}  // namespace bouncecal
