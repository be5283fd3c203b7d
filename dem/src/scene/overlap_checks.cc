#include "scene/overlap_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bouncecal/error.h"
#include "scene/cell_grid.h"

namespace bouncecal::dem::scene {

using particle_file::FileParticle;
using particle_file::Position;
using particle_file::Where;

namespace {

Vec<3> GridPoint(const Vec3& x) { return Vec<3>{{x[0], x[1], x[2]}}; }

// The box the placement grid covers: the region's bounding box widened by `margin`, flat in 2D.
CellGrid<3> PlacementGrid(const RegionSpec& region, int dimension, double margin,
                          double max_cells) {
  Vec<3> lo = Vec<3>::Zero();
  Vec<3> hi = Vec<3>::Zero();
  if (region.kind == RegionKind::kBox) {
    for (int d = 0; d < dimension; ++d) {
      lo[d] = region.min_m[d] - margin;
      hi[d] = region.max_m[d] + margin;
    }
  } else {
    for (int d = 0; d < 2; ++d) {
      lo[d] = region.center_m[d] - region.radius_m - margin;
      hi[d] = region.center_m[d] + region.radius_m + margin;
    }
    lo[2] = region.z_min_m - margin;
    hi[2] = region.z_max_m + margin;
  }
  if (dimension == 2) lo[2] = hi[2] = 0;
  return CellGrid<3>(lo, hi, margin, max_cells);
}

// A start file spread over more than the cell grid (and so the engine's pair list) covers:
// refused naming the two particles furthest apart along the first such axis. A misplaced row
// far away would otherwise leave the engine without any contact search.
[[noreturn]] void RefuseSpan(const std::vector<FileParticle>& particles,
                             const std::filesystem::path& path, int dimension, double limit_m) {
  static constexpr char kAxis[] = "xyz";
  for (int d = 0; d < dimension; ++d) {
    std::size_t lo = 0;
    std::size_t hi = 0;
    for (std::size_t i = 1; i < particles.size(); ++i) {
      if (particles[i].particle.position_m[d] < particles[lo].particle.position_m[d]) lo = i;
      if (particles[i].particle.position_m[d] > particles[hi].particle.position_m[d]) hi = i;
    }
    const double span = particles[hi].particle.position_m[d] - particles[lo].particle.position_m[d];
    if (!(span <= limit_m)) {
      throw InputError(fmt::format(
          "{}: the particle at {} lies {:.3g} m along {} from the particle on line {}, more than "
          "the {:.0e} m a packing can span; fix the misplaced row",
          Where(path, particles[hi].line), Position(particles[hi].particle.position_m, dimension),
          span, kAxis[d], particles[lo].line, limit_m));
    }
  }
  // Finite positions spanning less than the limit always give a grid.
  throw InputError(path.string() + ": the particles' positions cannot be searched for contacts");
}

// A grid of cells at least one largest radius wide (the shared cell grid, cell_grid.h) holds
// every heavily overlapping pair in neighbouring cells: the distance is below
// 0.5 (r_i + r_j) <= r_max.
template <int Dim>
void RefuseHeavyOverlapsIn(const std::vector<FileParticle>& particles,
                           const std::filesystem::path& path) {
  const int dimension = Dim;
  double r_max = 0;
  std::vector<Vec<Dim>> x(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    r_max = std::max(r_max, particles[i].particle.radius_m);
    for (int d = 0; d < Dim; ++d) x[i][d] = particles[i].particle.position_m[d];
  }
  const CellGrid<Dim> grid = CellGrid<Dim>::Covering(x, r_max);
  if (!grid.valid()) RefuseSpan(particles, path, dimension, CellGrid<Dim>::kMaxSpanM);
  const CellBins bins = BinByCell(grid, x);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const NewParticle& p = particles[i].particle;
    // The earliest particle of the file that p overlaps, so the message is the same whatever
    // the cell order.
    std::size_t partner = i;
    double partner_distance = 0;
    grid.ForEachNeighbour(grid.CoordOf(x[i]), [&](std::int64_t cell) {
      for (std::int32_t s = bins.start[cell]; s < bins.start[cell + 1]; ++s) {
        const auto j = static_cast<std::size_t>(bins.sorted[s]);
        if (j >= partner) break;  // a cell holds its particles in file order
        const NewParticle& q = particles[j].particle;
        double dist2 = 0;
        for (int d = 0; d < dimension; ++d) {
          dist2 += (p.position_m[d] - q.position_m[d]) * (p.position_m[d] - q.position_m[d]);
        }
        const double limit = 0.5 * (p.radius_m + q.radius_m);
        if (dist2 < limit * limit) {
          partner = j;
          partner_distance = std::sqrt(dist2);
        }
      }
    });
    if (partner != i) {
      const NewParticle& q = particles[partner].particle;
      throw InputError(fmt::format(
          "{}: particle at {} lies {:.9g} m from the particle on line {}, closer than half the "
          "sum of their radii ({:.9g} m): a duplicated row or an unsettled pack; remove the "
          "duplicate or space them out",
          Where(path, particles[i].line), Position(p.position_m, dimension), partner_distance,
          particles[partner].line, 0.5 * (p.radius_m + q.radius_m)));
    }
  }
}

}  // namespace

PlacedParticles::PlacedParticles(const RegionSpec& region, int dimension, double r_max_m,
                                 std::size_t expected)
    : grid_(PlacementGrid(region, dimension, 2 * r_max_m,
                          8.0 * static_cast<double>(expected) + 1024)) {
  // The scene checks make the region finite; a grid over it always exists.
  if (!grid_.valid()) throw ConfigError("insertion.region is not finite");
  lists_ = CellLists(grid_.cells());
}

void PlacedParticles::Add(const NewParticle& p) {
  lists_.Add(grid_.IndexOf(GridPoint(p.position_m)));
  placed_.push_back(p);
}

bool PlacedParticles::Overlaps(const Vec3& x, double r) const {
  bool overlaps = false;
  grid_.ForEachNeighbour(grid_.CoordOf(GridPoint(x)), [&](std::int64_t cell) {
    overlaps = overlaps || lists_.AnyIn(cell, [&](std::int32_t k) {
      const NewParticle& o = placed_[static_cast<std::size_t>(k)];
      double dist2 = 0;
      for (int d = 0; d < 3; ++d) {
        dist2 += (x[d] - o.position_m[d]) * (x[d] - o.position_m[d]);
      }
      const double touch = r + o.radius_m;
      return dist2 < touch * touch;
    });
  });
  return overlaps;
}

void RefuseHeavyOverlaps(const std::vector<FileParticle>& particles,
                         const std::filesystem::path& path, int dimension) {
  if (dimension == 3) {
    RefuseHeavyOverlapsIn<3>(particles, path);
  } else {
    RefuseHeavyOverlapsIn<2>(particles, path);
  }
}

}  // namespace bouncecal::dem::scene
