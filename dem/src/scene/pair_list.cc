#include "scene/pair_list.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

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

// A uniform grid of cells at least 2 r_max + reach_m wide over the particles' bounding box.
template <int Dim>
struct CellGrid {
  bool valid = false;  // false: a blown-up state (non-finite or astronomically far positions)
  Vec<Dim> lo = Vec<Dim>::Zero();
  std::array<std::int64_t, Dim> dims{};
  double inv_cell = 0;
  std::int64_t total_cells = 1;

  std::array<std::int64_t, Dim> Coord(const Vec<Dim>& x) const {
    std::array<std::int64_t, Dim> c{};
    for (int d = 0; d < Dim; ++d) {
      c[d] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[d] - lo[d]) * inv_cell), 0,
                                      dims[d] - 1);
    }
    return c;
  }
  std::int64_t Index(const std::array<std::int64_t, Dim>& c) const {
    std::int64_t index = 0;
    for (int d = Dim - 1; d >= 0; --d) index = index * dims[d] + c[d];
    return index;
  }
};

template <int Dim>
CellGrid<Dim> MakeCellGrid(const std::vector<Vec<Dim>>& position_m,
                           const std::vector<double>& radius_m, double reach_m) {
  const auto n = static_cast<std::int32_t>(position_m.size());
  CellGrid<Dim> grid;
  if (n == 0) return grid;
  Vec<Dim> lo = position_m[0];
  Vec<Dim> hi = position_m[0];
  double r_max = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    if (!position_m[i].allFinite()) return grid;
    lo = lo.cwiseMin(position_m[i]);
    hi = hi.cwiseMax(position_m[i]);
    r_max = std::max(r_max, radius_m[i]);
  }
  // A blown-up run gets no pairs; the engine reports it as unstable at its next check instead
  // of hanging here.
  for (int d = 0; d < Dim; ++d) {
    if (!(hi[d] - lo[d] <= 1e12)) return grid;
  }
  double cell_m = 2 * r_max + reach_m;
  // A particle flung far away must not make the grid huge: widen the cells instead (the pairs
  // found stay exact, only the search gets slower).
  const double max_cells = 8.0 * n + 1024;
  for (;;) {
    double cells = 1;
    for (int d = 0; d < Dim; ++d) cells *= std::floor((hi[d] - lo[d]) / cell_m) + 1;
    if (cells <= max_cells) break;
    cell_m *= 1.5;
  }
  grid.valid = true;
  grid.lo = lo;
  for (int d = 0; d < Dim; ++d) {
    grid.dims[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / cell_m)) + 1;
    grid.total_cells *= grid.dims[d];
  }
  grid.inv_cell = 1.0 / cell_m;
  return grid;
}

}  // namespace

template <int Dim>
std::vector<std::int32_t> CellOrder(const std::vector<Vec<Dim>>& position_m,
                                    const std::vector<double>& radius_m, double reach_m) {
  const auto n = static_cast<std::int32_t>(position_m.size());
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  const CellGrid<Dim> grid = MakeCellGrid<Dim>(position_m, radius_m, reach_m);
  if (!grid.valid) return order;
  std::vector<std::int64_t> cell_of(static_cast<std::size_t>(n));
  std::vector<std::int32_t> cell_start(static_cast<std::size_t>(grid.total_cells) + 1, 0);
  for (std::int32_t i = 0; i < n; ++i) {
    cell_of[i] = grid.Index(grid.Coord(position_m[i]));
    ++cell_start[static_cast<std::size_t>(cell_of[i]) + 1];
  }
  for (std::int64_t c = 0; c < grid.total_cells; ++c) cell_start[c + 1] += cell_start[c];
  for (std::int32_t i = 0; i < n; ++i)
    order[static_cast<std::size_t>(cell_start[cell_of[i]]++)] = i;
  return order;
}

template <int Dim>
PairList GridPairs(const std::vector<Vec<Dim>>& position_m, const std::vector<double>& radius_m,
                   double reach_m, WorkerPool* pool) {
  const auto n = static_cast<std::int32_t>(position_m.size());
  PairList list;
  const CellGrid<Dim> grid = MakeCellGrid<Dim>(position_m, radius_m, reach_m);
  if (!grid.valid) {
    list.BuildIndex(n);
    return list;
  }
  const auto& dims = grid.dims;
  auto cell_coord = [&](const Vec<Dim>& x) { return grid.Coord(x); };
  auto cell_index = [&](const std::array<std::int64_t, Dim>& c) { return grid.Index(c); };
  const std::int64_t total_cells = grid.total_cells;

  // Counting sort of particles by cell; within a cell particles stay in index order.
  std::vector<std::int64_t> cell_of(static_cast<std::size_t>(n));
  std::vector<std::int32_t> cell_start(static_cast<std::size_t>(total_cells) + 1, 0);
  for (std::int32_t i = 0; i < n; ++i) {
    cell_of[i] = cell_index(cell_coord(position_m[i]));
    ++cell_start[static_cast<std::size_t>(cell_of[i]) + 1];
  }
  for (std::int64_t c = 0; c < total_cells; ++c) cell_start[c + 1] += cell_start[c];
  std::vector<std::int32_t> sorted(static_cast<std::size_t>(n));
  {
    std::vector<std::int32_t> fill(cell_start.begin(), cell_start.end() - 1);
    for (std::int32_t i = 0; i < n; ++i) sorted[static_cast<std::size_t>(fill[cell_of[i]]++)] = i;
  }
  // Particles already in cell order (the engine sorts them at each rebuild with this grid): a
  // partner j > i then lies in i's cell or a later one, so the earlier cells of the stencil
  // need not be read (half the distance tests). The pairs found are the same.
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
      const auto c = cell_coord(position_m[i]);
      std::array<std::int64_t, Dim> lo_c{};
      std::array<std::int64_t, Dim> hi_c{};
      for (int d = 0; d < Dim; ++d) {
        lo_c[d] = std::max<std::int64_t>(c[d] - 1, 0);
        hi_c[d] = std::min<std::int64_t>(c[d] + 1, dims[d] - 1);
      }
      std::array<std::int64_t, Dim> k = lo_c;
      for (;;) {
        const std::int64_t cell = cell_index(k);
        const std::int32_t from =
            cell_ordered ? std::max(cell_start[cell], i + 1) : cell_start[cell];
        for (std::int32_t s = from; s < cell_start[cell + 1]; ++s) {
          const std::int32_t j = sorted[static_cast<std::size_t>(s)];
          if (j <= i) continue;
          const double reach = radius_m[i] + radius_m[j] + reach_m;
          if ((position_m[i] - position_m[j]).squaredNorm() < reach * reach) found.push_back(j);
        }
        int d = 0;
        for (; d < Dim; ++d) {
          if (++k[d] <= hi_c[d]) break;
          k[d] = lo_c[d];
        }
        if (d == Dim) break;
      }
      std::sort(found.begin(), found.end());
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
