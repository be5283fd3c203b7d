#ifndef BOUNCECAL_DEM_SCENE_PAIR_LIST_H_
#define BOUNCECAL_DEM_SCENE_PAIR_LIST_H_

#include <cstdint>
#include <vector>

#include "bouncecal/worker_pool.h"
#include "scene/vec.h"

namespace bouncecal::dem::scene {

// Candidate particle pairs (i < j), sorted by (i, j), in compressed-row form both ways so that a
// thread can sum the forces of one particle over its pairs in a fixed order without atomics:
// pairs whose first member is i are [begin[i], begin[i+1]); the pairs whose second member is i
// are reverse_pairs[reverse_begin[i] .. reverse_begin[i+1]), in increasing pair index.
struct PairList {
  std::vector<std::int32_t> first;
  std::vector<std::int32_t> second;
  std::vector<std::int32_t> begin;
  std::vector<std::int32_t> reverse_begin;
  std::vector<std::int32_t> reverse_pairs;

  std::size_t size() const { return first.size(); }
  // Fills begin/reverse_* from first/second (which must be sorted) for n particles.
  void BuildIndex(std::int32_t n);
};

// Every pair i < j: the O(N^2) reference the cell grid is tested against.
PairList AllPairs(std::int32_t n);

// The particles ordered by the cell of the grid GridPairs uses (x fastest, then y, then z),
// stable within a cell: order[k] is the particle to put k-th. Neighbours then sit close together
// in memory, and a thread's contiguous range of particles is a compact region.
template <int Dim>
std::vector<std::int32_t> CellOrder(const std::vector<Vec<Dim>>& position_m,
                                    const std::vector<double>& radius_m, double reach_m);

// Pairs whose surfaces are closer than `reach_m` (centre distance < r_i + r_j + reach_m), found
// with a uniform cell grid of cells at least 2 r_max + reach_m wide. Deterministic: the result
// does not depend on the thread count. With a pool the particles are searched in parallel.
template <int Dim>
PairList GridPairs(const std::vector<Vec<Dim>>& position_m, const std::vector<double>& radius_m,
                   double reach_m, WorkerPool* pool = nullptr);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_PAIR_LIST_H_
