#ifndef BOUNCECAL_DEM_PACKING_MEASURES_H_
#define BOUNCECAL_DEM_PACKING_MEASURES_H_

#include <cstdint>
#include <vector>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem {

// The particles of a scene at one instant (2D scenes leave z at 0).
struct ParticleSnapshot {
  int dimension = 3;
  double time_s = 0;
  std::int64_t step = 0;
  std::vector<Vec3> position_m;
  std::vector<Vec3> velocity_mps;
  std::vector<double> radius_m;
  std::vector<std::int32_t> species;
  std::size_t size() const { return position_m.size(); }
};

// Exact volume of the part of a sphere (centre height center_z_m) between two heights:
// V = pi [r^2 u - u^3/3] between the clipped limits u = z - center_z in [-r, r].
double SphereSlabVolumeM3(double center_z_m, double radius_m, double z_lo_m, double z_hi_m);

// Exact area of the intersection of a disk and an axis-aligned rectangle (closed form from the
// antiderivative of the chord length, no sampling).
double DiskRectangleAreaM2(double center_x_m, double center_y_m, double radius_m, double x_lo_m,
                           double y_lo_m, double x_hi_m, double y_hi_m);

// Solid fraction in the scene's measurement band (3D: sphere volume between band_min_m and
// band_max_m over the container cross-section) or window (2D: disk area over window area).
// Throws ConfigError when the scene has no band/window or no finite cross-section.
double PackingDensity(const ParticleSnapshot& snapshot, const Scene& scene);

// Paper 004's own estimator (its section 2): count the particles whose centres lie in the window
// (2D) or band (3D) and divide their whole areas (volumes) by the window's (the band's). Equal to
// PackingDensity on average in a homogeneous packing, but it jumps by one particle's share when a
// centre crosses an edge, so layers aligned with an edge bias it (by several % in ordered 2D
// packings). Same ConfigErrors as PackingDensity.
double CentreCountDensity(const ParticleSnapshot& snapshot, const Scene& scene);

// At most this many bins in a density profile.
inline constexpr double kMaxProfileBins = 1e6;

struct DensityProfile {
  std::vector<double> height_m;  // bin centres (z in 3D, y in 2D)
  std::vector<double> density;   // solid fraction of each horizontal slab of the container
};
// Paper 000 Fig. 7: solid fraction of slabs of bin_m from the floor up to the highest particle.
DensityProfile DensityProfileVsHeight(const ParticleSnapshot& snapshot, const Scene& scene,
                                      double bin_m);

struct CoordinationStats {
  std::vector<std::int64_t> histogram;  // histogram[z]: particles with z touching neighbours
  double mean = 0;
  std::int64_t particles = 0;  // particles counted (centre inside the band or window)
};
// Particles touch when their centres are closer than tolerance (r_i + r_j) (paper 004: 1.0005 d).
// Counted for particles whose centre lies in the band (3D) or window (2D); their neighbours may
// lie anywhere. Wall contacts are not counted.
CoordinationStats Coordination(const ParticleSnapshot& snapshot, const Scene& scene);

// Cross-sectional area (3D) or width (2D) of the container at the measurement band; ConfigError
// when the container is open sideways (a lone plane).
double ContainerCrossSection(const Scene& scene);

// Height (z in 3D, y in 2D) of the container's floor, and of its top: a cylinder's rim, a box's
// top face (open or not); +infinity for a lone plane.
double ContainerFloorM(const Scene& scene);
double ContainerTopM(const Scene& scene);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_PACKING_MEASURES_H_
