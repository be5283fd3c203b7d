#include "scene/worker_pool.h"

namespace bouncecal::dem::scene {
namespace {

// About 5-10 us of polling before sleeping: long enough to catch the next loop of the same
// step without a system call, short enough to give the core away on a busy machine.
constexpr int kSpinIterations = 200;

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

WorkerPool::WorkerPool(int threads) {
  for (int chunk = 1; chunk < threads; ++chunk) {
    workers_.emplace_back([this, chunk] { WorkerLoop(chunk); });
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

void WorkerPool::ParallelFor(std::int64_t n,
                             const std::function<void(int, std::int64_t, std::int64_t)>& body) {
  if (workers_.empty()) {
    if (n > 0) body(0, 0, n);
    return;
  }
  body_ = &body;
  n_ = n;
  pending_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_acq_rel);  // publishes body_ and n_
  generation_.notify_all();
  RunChunk(0);
  int spins = 0;
  for (int left = pending_.load(std::memory_order_acquire); left != 0;
       left = pending_.load(std::memory_order_acquire)) {
    if (++spins < kSpinIterations) {
      CpuRelax();
    } else {
      pending_.wait(left, std::memory_order_acquire);
    }
  }
}

void WorkerPool::WorkerLoop(int chunk) {
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
    RunChunk(chunk);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_all();
  }
}

}  // namespace bouncecal::dem::scene
