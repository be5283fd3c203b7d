#include "scene/cell_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <vector>

#include "scene/insertion.h"

namespace bouncecal::dem::scene {
namespace {

// The cells a search visits from x: x's cell and its neighbours.
template <int Dim>
std::set<std::int64_t> VisitedFrom(const CellGrid<Dim>& grid, const Vec<Dim>& x) {
  std::set<std::int64_t> cells;
  std::int64_t previous = -1;
  grid.ForEachNeighbour(grid.CoordOf(x), [&](std::int64_t cell) {
    EXPECT_GT(cell, previous) << "cells are visited in increasing index";
    previous = cell;
    cells.insert(cell);
  });
  return cells;
}

// The property every search relies on, checked against all pairs: two points closer than the
// cell width lie in neighbouring cells, also when the grid's box does not hold them (clamped
// into its edge cells) and when its cells were widened.
template <int Dim>
void ExpectClosePointsInNeighbouringCells(double max_cells, std::uint64_t seed) {
  SceneRandom random(seed);
  const double width_m = 0.01;
  Vec<Dim> lo;
  Vec<Dim> hi;
  for (int d = 0; d < Dim; ++d) {
    lo[d] = 0;
    hi[d] = 0.1;
  }
  const CellGrid<Dim> grid(lo, hi, width_m, max_cells);
  ASSERT_TRUE(grid.valid());
  std::vector<Vec<Dim>> x(600);
  for (auto& p : x) {
    for (int d = 0; d < Dim; ++d) p[d] = random.Uniform(-0.03, 0.13);  // some outside the box
  }
  int close = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto visited = VisitedFrom(grid, x[i]);
    for (std::size_t j = 0; j < x.size(); ++j) {
      if (j == i || (x[i] - x[j]).norm() >= width_m) continue;
      ++close;
      EXPECT_EQ(visited.count(grid.IndexOf(x[j])), 1u) << "points " << i << " and " << j;
    }
  }
  // Enough close pairs to mean something (about 370 expected in 3D, 3000 in 2D).
  EXPECT_GT(close, 150);
}

TEST(CellGrid, PointsCloserThanACellLieInNeighbouringCells) {
  ExpectClosePointsInNeighbouringCells<3>(1e9, 1);
  ExpectClosePointsInNeighbouringCells<2>(1e9, 2);
}

TEST(CellGrid, WidenedCellsStillHoldEveryCloseNeighbour) {
  ExpectClosePointsInNeighbouringCells<3>(50, 3);
  ExpectClosePointsInNeighbouringCells<2>(20, 4);
}

// A far outlier widens the cells instead of asking for (1e3 / 1e-3)^3 of them.
TEST(CellGrid, AFarOutlierWidensTheCellsInsteadOfGrowingTheGrid) {
  std::vector<Vec<3>> x(100, Vec<3>::Zero());
  for (std::size_t i = 0; i < x.size(); ++i) x[i][0] = 0.001 * static_cast<double>(i);
  x.back() = Vec<3>{{1e3, 1e3, 1e3}};
  const auto grid = CellGrid<3>::Covering(x, 0.001);
  ASSERT_TRUE(grid.valid());
  EXPECT_LE(grid.cells(), 8 * 100 + 1024);
  EXPECT_GT(grid.cells(), 1);
}

TEST(CellGrid, NonFiniteOrAstronomicalSpansGiveNoGrid) {
  std::vector<Vec<3>> x = {Vec<3>::Zero(), Vec<3>{{0.001, 0, 0}}};
  EXPECT_TRUE(CellGrid<3>::Covering(x, 0.001).valid());
  EXPECT_FALSE(CellGrid<3>::Covering({}, 0.001).valid());
  x[1][2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(CellGrid<3>::Covering(x, 0.001).valid());
  x[1][2] = 2 * CellGrid<3>::kMaxSpanM;
  EXPECT_FALSE(CellGrid<3>::Covering(x, 0.001).valid());
}

// The counting sort keeps the points of a cell in their order and visits every point once.
TEST(CellGrid, BinsHoldEveryPointOnceInOrderWithinACell) {
  SceneRandom random(5);
  std::vector<Vec<2>> x(300);
  for (auto& p : x) p = Vec<2>{{random.Uniform(0, 0.1), random.Uniform(0, 0.1)}};
  const auto grid = CellGrid<2>::Covering(x, 0.01);
  ASSERT_TRUE(grid.valid());
  const CellBins bins = BinByCell(grid, x);
  std::vector<int> seen(x.size(), 0);
  for (std::int64_t c = 0; c < grid.cells(); ++c) {
    for (std::int32_t s = bins.start[c]; s < bins.start[c + 1]; ++s) {
      const std::int32_t i = bins.sorted[s];
      ++seen[i];
      EXPECT_EQ(grid.IndexOf(x[i]), c);
      if (s > bins.start[c]) {
        EXPECT_LT(bins.sorted[s - 1], i);
      }
    }
  }
  for (int count : seen) EXPECT_EQ(count, 1);
}

}  // namespace
}  // namespace bouncecal::dem::scene
