#include "scene/pair_list.h"

#include <algorithm>

#include "scene/cell_grid.h"

namespace bouncecal::dem::scene {

void PairList::BuildIndex(std::int32_t n) {
  begin.assign(static_cast<std::size_t>(n) + 1, 0);
  reverse_begin.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t p = 0; p < first.size(); ++p) {
    ++begin[static_cast<std::size_t>(first[p]) + 1];
    ++reverse_begin[static_cast<std::size_t>(second[p]) + 1];
  }
  for (std::int32_t i = 0; i < n; ++i) {
    begin[i + 1] += begin[i];
    reverse_begin[i + 1] += reverse_begin[i];
  }
  reverse_pairs.resize(first.size());
  std::vector<std::int32_t> fill(reverse_begin.begin(), reverse_begin.end() - 1);
  // Increasing p keeps each particle's reverse pairs in pair order, so sums have a fixed order.
  for (std::size_t p = 0; p < first.size(); ++p) {
    reverse_pairs[static_cast<std::size_t>(fill[second[p]]++)] = static_cast<std::int32_t>(p);
  }
}

PairList AllPairs(std::int32_t n) {
  PairList list;
  const std::size_t count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n - 1) / 2;
  list.first.reserve(count);
  list.second.reserve(count);
  for (std::int32_t i = 0; i < n; ++i) {
    for (std::int32_t j = i + 1; j < n; ++j) {
      list.first.push_back(i);
      list.second.push_back(j);
    }
  }
  list.BuildIndex(n);
  return list;
}

namespace {

// The grid of the pair list and of the cell order: cells at least 2 r_max + reach_m wide over
// the particles' bounding box. A blown-up state (non-finite or astronomically far positions)
// gets no grid, hence no pairs: the engine reports it as unstable at its next check instead of
// hanging here.
template <int Dim>
CellGrid<Dim> PairGrid(const std::vector<Vec<Dim>>& position_m, const std::vector<double>& radius_m,
                       double reach_m) {
  double r_max = 0;
  for (const double r : radius_m) r_max = std::max(r_max, r);
  return CellGrid<Dim>::Covering(position_m, 2 * r_max + reach_m);
}

}  // namespace

template <int Dim>
std::vector<std::int32_t> CellOrder(const std::vector<Vec<Dim>>& position_m,
                                    const std::vector<double>& radius_m, double reach_m) {
  const auto n = static_cast<std::int32_t>(position_m.size());
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  const CellGrid<Dim> grid = PairGrid<Dim>(position_m, radius_m, reach_m);
  if (!grid.valid()) return order;
  return BinByCell(grid, position_m).sorted;
}

template <int Dim>
PairList GridPairs(const std::vector<Vec<Dim>>& position_m, const std::vector<double>& radius_m,
                   double reach_m, WorkerPool* pool) {
  const auto n = static_cast<std::int32_t>(position_m.size());
  PairList list;
  const CellGrid<Dim> grid = PairGrid<Dim>(position_m, radius_m, reach_m);
  if (!grid.valid()) {
    list.BuildIndex(n);
    return list;
  }
  // Particles sorted by cell; within a cell they stay in index order.
  const CellBins bins = BinByCell(grid, position_m);
  const std::int32_t* cell_start = bins.start.data();
  const std::int32_t* sorted = bins.sorted.data();
  // Particles already in cell order (the engine sorts them at each rebuild with this grid): a
  // partner j > i then lies in i's cell or a later one, so only the rows of the stencil from
  // i's own on are read, each as one run of points (ForEachLaterRow). The pairs found are the
  // same.
  bool cell_ordered = true;
  for (std::int32_t s = 0; s < n && cell_ordered; ++s) cell_ordered = sorted[s] == s;

  // Each chunk of particles lists its pairs on its own; the chunks are joined in order, so the
  // list is the same for any pool.
  const int chunks = pool != nullptr ? pool->chunks() : 1;
  std::vector<PairList> parts(static_cast<std::size_t>(chunks));
  auto find_pairs = [&](int chunk, std::int64_t begin, std::int64_t end) {
    PairList& part = parts[static_cast<std::size_t>(chunk)];
    part.first.reserve(static_cast<std::size_t>(end - begin) * (Dim == 3 ? 8 : 4));
    part.second.reserve(part.first.capacity());
    std::vector<std::int32_t> found;
    for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
      found.clear();
      auto test = [&](std::int32_t j) {
        const double reach = radius_m[i] + radius_m[j] + reach_m;
        if ((position_m[i] - position_m[j]).squaredNorm() < reach * reach) found.push_back(j);
      };
      if (cell_ordered) {
        // Rows in increasing index and points in cell order: found comes out sorted.
        grid.ForEachLaterRow(
            grid.CoordOf(position_m[i]), [&](std::int64_t first_cell, std::int64_t last_cell) {
              const std::int32_t stop = cell_start[last_cell + 1];
              for (std::int32_t j = std::max(cell_start[first_cell], i + 1); j < stop; ++j) {
                test(j);
              }
            });
      } else {
        grid.ForEachNeighbour(grid.CoordOf(position_m[i]), [&](std::int64_t cell) {
          for (std::int32_t s = cell_start[cell]; s < cell_start[cell + 1]; ++s) {
            if (sorted[s] > i) test(sorted[s]);
          }
        });
        std::sort(found.begin(), found.end());
      }
      for (std::int32_t j : found) {
        part.first.push_back(i);
        part.second.push_back(j);
      }
    }
  };
  if (pool != nullptr) {
    pool->ParallelFor(n, find_pairs);
  } else {
    find_pairs(0, 0, n);
  }
  std::size_t total = 0;
  for (const auto& part : parts) total += part.size();
  list.first.reserve(total);
  list.second.reserve(total);
  for (const auto& part : parts) {
    list.first.insert(list.first.end(), part.first.begin(), part.first.end());
    list.second.insert(list.second.end(), part.second.begin(), part.second.end());
  }
  list.BuildIndex(n);
  return list;
}

template std::vector<std::int32_t> CellOrder<2>(const std::vector<Vec<2>>&,
                                                const std::vector<double>&, double);
template std::vector<std::int32_t> CellOrder<3>(const std::vector<Vec<3>>&,
                                                const std::vector<double>&, double);
template PairList GridPairs<2>(const std::vector<Vec<2>>&, const std::vector<double>&, double,
                               WorkerPool*);
template PairList GridPairs<3>(const std::vector<Vec<3>>&, const std::vector<double>&, double,
                               WorkerPool*);

}  // namespace bouncecal::dem::scene
