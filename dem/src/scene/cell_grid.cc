#include "scene/cell_grid.h"

#include <cmath>

namespace bouncecal::dem::scene {

template <int Dim>
CellGrid<Dim>::CellGrid(const Vec<Dim>& lo, const Vec<Dim>& hi, double min_cell_m,
                        double max_cells) {
  for (int d = 0; d < Dim; ++d) {
    if (!std::isfinite(lo[d]) || !std::isfinite(hi[d]) || !std::isfinite(hi[d] - lo[d])) return;
  }
  double cell_m = min_cell_m;
  for (;;) {
    double cells = 1;
    for (int d = 0; d < Dim; ++d) cells *= std::floor((hi[d] - lo[d]) / cell_m) + 1;
    if (cells <= max_cells) break;
    cell_m *= 1.5;
  }
  valid_ = true;
  lo_ = lo;
  total_cells_ = 1;
  for (int d = 0; d < Dim; ++d) {
    dims_[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / cell_m)) + 1;
    total_cells_ *= dims_[d];
  }
  inv_cell_ = 1.0 / cell_m;
}

template <int Dim>
CellGrid<Dim> CellGrid<Dim>::Covering(const std::vector<Vec<Dim>>& x, double min_cell_m) {
  if (x.empty()) return {};
  Vec<Dim> lo = x[0];
  Vec<Dim> hi = x[0];
  for (const auto& p : x) {
    if (!p.allFinite()) return {};
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (int d = 0; d < Dim; ++d) {
    if (!(hi[d] - lo[d] <= kMaxSpanM)) return {};
  }
  return CellGrid(lo, hi, min_cell_m, 8.0 * static_cast<double>(x.size()) + 1024);
}

template <int Dim>
CellBins BinByCell(const CellGrid<Dim>& grid, const std::vector<Vec<Dim>>& x) {
  const auto n = static_cast<std::int32_t>(x.size());
  CellBins bins;
  bins.cell_of.resize(x.size());
  bins.start.assign(static_cast<std::size_t>(grid.cells()) + 1, 0);
  for (std::int32_t i = 0; i < n; ++i) {
    bins.cell_of[i] = grid.IndexOf(x[i]);
    ++bins.start[static_cast<std::size_t>(bins.cell_of[i]) + 1];
  }
  for (std::int64_t c = 0; c < grid.cells(); ++c) bins.start[c + 1] += bins.start[c];
  bins.sorted.resize(x.size());
  std::vector<std::int32_t> fill(bins.start.begin(), bins.start.end() - 1);
  for (std::int32_t i = 0; i < n; ++i) {
    bins.sorted[static_cast<std::size_t>(fill[bins.cell_of[i]]++)] = i;
  }
  return bins;
}

template class CellGrid<2>;
template class CellGrid<3>;
template CellBins BinByCell<2>(const CellGrid<2>&, const std::vector<Vec<2>>&);
template CellBins BinByCell<3>(const CellGrid<3>&, const std::vector<Vec<3>>&);

}  // namespace bouncecal::dem::scene
