#ifndef BOUNCECAL_WORKER_POOL_H_
#define BOUNCECAL_WORKER_POOL_H_

#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace bouncecal {

// The project's one pool of worker threads: the packing engine's two short parallel loops of
// every DEM step (ParallelFor), and calibration's few long tasks, such as one fit per contact law
// (ParallelForEach). Persistent threads for the two short parallel loops of every DEM step. A step
// of a few thousand particles takes ~100 us, so the hand-off must be cheap, yet the machine may be
// shared: OpenMP's default spin-waiting made a 2-thread run many times slower than 1 thread on a
// loaded machine. Waiters poll for up to ~100 us, then sleep on a futex (C++20 atomic wait). Chunks
// are fixed contiguous ranges, so work splits identically on every run, but any thread may run any
// chunk: when the machine is busy and a worker has no core, the caller runs its chunks instead of
// waiting a scheduler slice for them (callers' results depend on the chunk, never on the thread
// that ran it). Each thread first claims its own "home" chunks (thread t: chunks t*k .. t*k + k -
// 1), then takes what is left of the others' from their far end: the engine's loops over pairs and
// over particles index the same region of space by the same chunk, so a thread keeps finding in its
// own cache the pair results it wrote, instead of fetching them from the other core's.
class WorkerPool {
 public:
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  // Chunks per loop: several per thread, so that a thread whose chunks are cheap (falling
  // particles with few contacts) claims more of them instead of waiting at the barrier for one
  // holding the dense bottom of a pour. 8 per thread waste less at the barrier than 4, and 16
  // gain nothing more. Callers size per-chunk scratch by this.
  int chunks() const { return workers_.empty() ? 1 : threads() * kChunksPerThread; }

  // Calls body(chunk, begin, end) once for each of chunks() contiguous chunks of [0, n), on
  // whichever thread claims the chunk first; one chunk runs on one thread. Returns when every
  // chunk is done.
  void ParallelFor(std::int64_t n,
                   const std::function<void(int, std::int64_t, std::int64_t)>& body);

  // Calls body(i) once for each i in [0, n), for few items that each take long (a whole fit):
  // unlike ParallelFor, a loop of a handful of items is still spread over the threads, each
  // item claimed by the first free thread. Callers' results must not depend on which thread ran
  // an item (they write item i's result to slot i). body must not throw: an exception cannot
  // cross from a worker to the caller, so catch it into the item's slot.
  void ParallelForEach(std::int64_t n, const std::function<void(std::int64_t)>& body);

 private:
  static constexpr int kChunksPerThread = 8;

  // Publishes a loop of n items to every thread and runs it (any n; ParallelFor's small loops
  // never get here).
  void RunOnAllThreads(std::int64_t n,
                       const std::function<void(int, std::int64_t, std::int64_t)>& body);
  void WorkerLoop(int thread);
  void RunChunk(int chunk);
  // Claims and runs chunks of the loop published as `generation` until none is left, its own
  // home chunks first.
  void RunClaimedChunks(int thread, std::uint64_t generation);
  bool Claim(int chunk, std::uint64_t generation);

  std::vector<std::thread> workers_;
  std::atomic<std::uint64_t> generation_{0};
  // Per chunk: 2g while it is open in the loop of generation g, 2g + 1 once claimed. A late
  // worker cannot claim a chunk of a newer loop as one of the loop it woke for.
  std::vector<std::atomic<std::uint64_t>> claims_;
  std::atomic<int> done_{0};  // chunks finished in the current loop
  std::atomic<bool> stop_{false};
  const std::function<void(int, std::int64_t, std::int64_t)>* body_ = nullptr;
  std::int64_t n_ = 0;
};

}  // namespace bouncecal

#endif  // BOUNCECAL_WORKER_POOL_H_
