#include "scene/overlap_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::dem::scene {

using particle_file::FileParticle;
using particle_file::Position;
using particle_file::Where;

namespace {

// A cell index of a grid of spacing `cell_m`, clamped so that any finite coordinate (a file may
// hold 1e300 beside 1e-6 radii) converts without overflow.
std::int64_t CellIndex(double x, double cell_m) {
  constexpr double kLimit = 0x1p62;
  const double c = std::floor(x / cell_m);
  return static_cast<std::int64_t>(std::clamp(c, -kLimit, kLimit));
}

}  // namespace

// A grid of cells one largest radius wide holds every heavily overlapping pair in neighbouring
// cells (the distance is below 0.5 (r_i + r_j) <= r_max); sorted by cell, each particle looks up
// its 27 (9 in 2D) neighbour cells by binary search, so a file of N particles costs O(N log N),
// not O(N^2).
void RefuseHeavyOverlaps(const std::vector<FileParticle>& particles,
                         const std::filesystem::path& path, int dimension) {
  double r_max = 0;
  for (const auto& f : particles) r_max = std::max(r_max, f.particle.radius_m);
  using Cell = std::array<std::int64_t, 3>;
  std::vector<Cell> cell_of(particles.size());
  std::vector<std::pair<Cell, std::size_t>> sorted(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& x = particles[i].particle.position_m;
    cell_of[i] = {CellIndex(x[0], r_max), CellIndex(x[1], r_max),
                  dimension == 3 ? CellIndex(x[2], r_max) : 0};
    sorted[i] = {cell_of[i], i};
  }
  std::sort(sorted.begin(), sorted.end());
  const std::int64_t dz = dimension == 3 ? 1 : 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const NewParticle& p = particles[i].particle;
    // The earliest particle of the file that p overlaps, so the message is the same whatever
    // the cell order.
    std::size_t partner = i;
    double partner_distance = 0;
    for (std::int64_t a = -1; a <= 1; ++a) {
      for (std::int64_t b = -1; b <= 1; ++b) {
        for (std::int64_t c = -dz; c <= dz; ++c) {
          const Cell key{cell_of[i][0] + a, cell_of[i][1] + b, cell_of[i][2] + c};
          auto it =
              std::lower_bound(sorted.begin(), sorted.end(), key,
                               [](const auto& entry, const Cell& k) { return entry.first < k; });
          for (; it != sorted.end() && it->first == key; ++it) {
            const std::size_t j = it->second;
            if (j >= partner) continue;
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
        }
      }
    }
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

}  // namespace bouncecal::dem::scene
