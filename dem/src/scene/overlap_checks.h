#ifndef BOUNCECAL_DEM_SCENE_OVERLAP_CHECKS_H_
#define BOUNCECAL_DEM_SCENE_OVERLAP_CHECKS_H_

// The two overlap questions of insertion: does a randomly drawn centre overlap a particle already
// placed (random and pour placement, insertion.cc), and does a start-positions file hold two
// particles that overlap heavily (particle_file.cc).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "bouncecal/dem/scene.h"
#include "scene/cell_grid.h"
#include "scene/insertion.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene {

// The particles placed so far in the insertion region, for the overlap test of each new centre
// (random and pour placement). Two particles overlap when their centres are closer than the sum
// of their radii, at most 2 r_max, so the shared cell grid (cell_grid.h) with cells that wide,
// over the region widened by as much, holds every particle a new one could touch in the
// neighbour cells of its centre. In 2D the grid has one layer (z = 0).
class PlacedParticles {
 public:
  // For particles of radius at most r_max_m, about `expected` of them (it sizes the grid).
  PlacedParticles(const RegionSpec& region, int dimension, double r_max_m, std::size_t expected);

  void Add(const NewParticle& p);
  // Whether a particle of radius r centred at x would overlap one placed.
  bool Overlaps(const Vec3& x, double r) const;

 private:
  CellGrid<3> grid_;
  CellLists lists_;
  std::vector<NewParticle> placed_;  // in the order of lists_' numbers
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
