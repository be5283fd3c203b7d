#ifndef BOUNCECAL_DEM_SCENE_CELL_GRID_H_
#define BOUNCECAL_DEM_SCENE_CELL_GRID_H_

// The one uniform cell grid behind every neighbour search of the scene code: the engine's pair
// list and particle order (pair_list.cc), the overlap test of random placement and the
// heavy-overlap check of start files (overlap_checks.cc). Cells are at least as wide as the
// largest distance searched for, so any two points closer than that lie in the same or in
// neighbouring cells (3^Dim of them). A point outside the grid's box is clamped into an edge
// cell, which keeps that property. The grid maps points to cells; CellBins (a fixed set) and
// CellLists (a set that grows) hold the points of each cell.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "scene/vec.h"

namespace bouncecal::dem::scene {

template <int Dim>
class CellGrid {
 public:
  using Coord = std::array<std::int64_t, Dim>;

  // Beyond this span (m) a set of points is taken for a blown-up state rather than a scene.
  static constexpr double kMaxSpanM = 1e12;

  // No cells (valid() is false).
  CellGrid() = default;
  // Cells at least min_cell_m wide over the box [lo, hi], widened (x1.5 at a time) until there
  // are at most max_cells of them: a far outlier must not make the grid huge (the neighbours
  // found stay exact, only the search gets slower). Invalid unless the box is finite.
  CellGrid(const Vec<Dim>& lo, const Vec<Dim>& hi, double min_cell_m, double max_cells);
  // The grid over the bounding box of `x`, at most 8 cells per point (plus 1024). Invalid when x
  // is empty, holds a non-finite point or spans more than kMaxSpanM.
  static CellGrid Covering(const std::vector<Vec<Dim>>& x, double min_cell_m);

  bool valid() const { return valid_; }
  std::int64_t cells() const { return total_cells_; }

  // The cell holding x (clamped into the grid).
  Coord CoordOf(const Vec<Dim>& x) const {
    Coord c{};
    for (int d = 0; d < Dim; ++d) {
      // Clamped as a double first, so a point far outside converts without overflow.
      const double cell =
          std::clamp((x[d] - lo_[d]) * inv_cell_, 0.0, static_cast<double>(dims_[d] - 1));
      c[d] = static_cast<std::int64_t>(cell);
    }
    return c;
  }
  // Cells are numbered x fastest, then y, then z.
  std::int64_t Index(const Coord& c) const {
    std::int64_t index = 0;
    for (int d = Dim - 1; d >= 0; --d) index = index * dims_[d] + c[d];
    return index;
  }
  std::int64_t IndexOf(const Vec<Dim>& x) const { return Index(CoordOf(x)); }

  // Calls visit(cell index) for the cell c and each of its neighbours inside the grid, in
  // increasing index.
  template <class Visit>
  [[gnu::always_inline]] inline void ForEachNeighbour(const Coord& c, Visit&& visit) const {
    Coord lo{};
    Coord hi{};
    for (int d = 0; d < Dim; ++d) {
      lo[d] = std::max<std::int64_t>(c[d] - 1, 0);
      hi[d] = std::min<std::int64_t>(c[d] + 1, dims_[d] - 1);
    }
    // Row by row (x fastest), so a cell's index is one addition from the previous one.
    if constexpr (Dim == 3) {
      for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
        for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
          const std::int64_t row = (z * dims_[1] + y) * dims_[0];
          for (std::int64_t x = lo[0]; x <= hi[0]; ++x) visit(row + x);
        }
      }
    } else {
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
        const std::int64_t row = y * dims_[0];
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) visit(row + x);
      }
    }
  }

  // For points numbered in cell order (x fastest, as BinByCell sorts them): calls visit(first,
  // last) for each row of c's neighbourhood that can hold a point numbered after one in c, as
  // the run of cells first .. last along x: c's own row and the rows after it (in 3D the next
  // row of c's layer and the three rows of the next layer; in 2D the next row). The other rows
  // hold only cells of lower index, so only earlier points. Rows in increasing index.
  template <class Visit>
  [[gnu::always_inline]] inline void ForEachLaterRow(const Coord& c, Visit&& visit) const {
    const std::int64_t x_lo = std::max<std::int64_t>(c[0] - 1, 0);
    const std::int64_t x_hi = std::min<std::int64_t>(c[0] + 1, dims_[0] - 1);
    auto row = [&](std::int64_t y, std::int64_t z) {
      if (y < 0 || y >= dims_[1]) return;
      if constexpr (Dim == 3) {
        if (z >= dims_[2]) return;
      }
      const std::int64_t first = (z * dims_[1] + y) * dims_[0];
      visit(first + x_lo, first + x_hi);
    };
    const std::int64_t z = Dim == 3 ? c[Dim - 1] : 0;
    row(c[1], z);
    row(c[1] + 1, z);
    if constexpr (Dim == 3) {
      for (std::int64_t y = c[1] - 1; y <= c[1] + 1; ++y) row(y, z + 1);
    }
  }

 private:
  bool valid_ = false;
  Vec<Dim> lo_ = Vec<Dim>::Zero();
  Coord dims_{};
  double inv_cell_ = 0;
  std::int64_t total_cells_ = 0;
};

// A fixed set of points sorted by cell (a counting sort, so stable: within a cell the points
// keep their order). The points of cell c are sorted[start[c]] .. sorted[start[c + 1] - 1].
struct CellBins {
  std::vector<std::int64_t> cell_of;  // per point
  std::vector<std::int32_t> start;    // per cell, and one past the last
  std::vector<std::int32_t> sorted;
};

// The points of x binned on a valid grid.
template <int Dim>
CellBins BinByCell(const CellGrid<Dim>& grid, const std::vector<Vec<Dim>>& x);

// A set of points that grows one at a time (random placement): a linked list per cell. The
// points are numbered in the order they are added.
class CellLists {
 public:
  CellLists() = default;
  explicit CellLists(std::int64_t cells) : head_(static_cast<std::size_t>(cells), -1) {}

  // Adds a point to `cell`; returns its number.
  std::int32_t Add(std::int64_t cell) {
    const auto point = static_cast<std::int32_t>(next_.size());
    next_.push_back(head_[static_cast<std::size_t>(cell)]);
    head_[static_cast<std::size_t>(cell)] = point;
    return point;
  }
  // Calls test(point) for the points of `cell` until one returns true; returns whether one did.
  template <class Test>
  bool AnyIn(std::int64_t cell, Test&& test) const {
    for (std::int32_t k = head_[static_cast<std::size_t>(cell)]; k >= 0;
         k = next_[static_cast<std::size_t>(k)]) {
      if (test(k)) return true;
    }
    return false;
  }

 private:
  std::vector<std::int32_t> head_;  // per cell, -1 when empty
  std::vector<std::int32_t> next_;  // per point, -1 at the end of its cell's list
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_CELL_GRID_H_
