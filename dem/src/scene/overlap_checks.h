#ifndef BOUNCECAL_DEM_SCENE_OVERLAP_CHECKS_H_
#define BOUNCECAL_DEM_SCENE_OVERLAP_CHECKS_H_

// The two overlap questions of insertion: does a randomly drawn centre overlap a particle already
// placed (random and pour placement, insertion.cc), and does a start-positions file hold two
// particles that overlap heavily (particle_file.cc).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <unordered_map>
#include <vector>

#include "scene/insertion.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene {

// The particles placed so far, for the overlap test of each new centre: a hash grid over the
// region.
class PlacementGrid {
 public:
  PlacementGrid(double cell_m, int dimension) : inv_cell_(1.0 / cell_m), dimension_(dimension) {}

  void Add(const NewParticle& p) {
    cells_[Key(Cell(p.position_m, 0), Cell(p.position_m, 1), Cell(p.position_m, 2))].push_back(
        particles_.size());
    particles_.push_back(p);
  }

  bool Overlaps(const Vec3& x, double r) const {
    const std::int64_t cx = Cell(x, 0);
    const std::int64_t cy = Cell(x, 1);
    const std::int64_t cz = Cell(x, 2);
    const int dz = dimension_ == 3 ? 1 : 0;
    for (std::int64_t a = cx - 1; a <= cx + 1; ++a) {
      for (std::int64_t b = cy - 1; b <= cy + 1; ++b) {
        for (std::int64_t c = cz - dz; c <= cz + dz; ++c) {
          const auto it = cells_.find(Key(a, b, c));
          if (it == cells_.end()) continue;
          for (std::size_t k : it->second) {
            const NewParticle& o = particles_[k];
            double dist2 = 0;
            for (int d = 0; d < 3; ++d)
              dist2 += (x[d] - o.position_m[d]) * (x[d] - o.position_m[d]);
            const double touch = r + o.radius_m;
            if (dist2 < touch * touch) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  std::int64_t Cell(const Vec3& x, int d) const {
    return static_cast<std::int64_t>(std::floor(x[d] * inv_cell_));
  }
  static std::uint64_t Key(std::int64_t a, std::int64_t b, std::int64_t c) {
    return (static_cast<std::uint64_t>(a) * 73856093ull) ^
           (static_cast<std::uint64_t>(b) * 19349663ull) ^
           (static_cast<std::uint64_t>(c) * 83492791ull);
  }

  double inv_cell_;
  int dimension_;
  std::vector<NewParticle> particles_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

// Throws InputError for a start file holding two particles closer than half the sum of their
// radii (a duplicated row or an unsettled pack: the contact law would fling them apart at the
// first step), naming both lines: the first such particle of the file and the earliest one it
// overlaps, so the message is the same whatever the grid's order. Also refuses a file whose
// particles span more than the cell grid covers (CellGrid::kMaxSpanM, 1e12 m: a misplaced row),
// which the engine could not search for contacts.
void RefuseHeavyOverlaps(const std::vector<particle_file::FileParticle>& particles,
                         const std::filesystem::path& path, int dimension);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_OVERLAP_CHECKS_H_
