#include "bouncecal/dem/packing_measures.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/insertion.h"

namespace bouncecal::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Simpson's rule on the cross-section pi (r^2 - u^2): exact for this quadratic integrand up to
// rounding, so it checks the closed form independently.
double SlabBySimpson(double zc, double r, double lo, double hi) {
  const double a = std::max(lo, zc - r);
  const double b = std::min(hi, zc + r);
  if (b <= a) return 0;
  auto area = [&](double z) { return kPi * (r * r - (z - zc) * (z - zc)); };
  return (b - a) / 6 * (area(a) + 4 * area(0.5 * (a + b)) + area(b));
}

// Midpoint rule over x of the clipped chord length; the integrand has square-root kinks where
// the rectangle edges cut the circle, so the error falls like h^1.5: 2e5 intervals give < 1e-7.
double DiskRectangleNumeric(double cx, double cy, double r, double x0, double y0, double x1,
                            double y1) {
  const double a = std::max(x0, cx - r);
  const double b = std::min(x1, cx + r);
  if (b <= a) return 0;
  const int n = 200000;
  const double h = (b - a) / n;
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    const double x = a + (k + 0.5) * h;
    const double s = std::sqrt(std::max(0.0, r * r - (x - cx) * (x - cx)));
    sum += std::max(0.0, std::min(y1, cy + s) - std::max(y0, cy - s));
  }
  return sum * h;
}

TEST(SphereSlabVolume, WholeAndHalfSphereAreExact) {
  const double r = 0.3;
  const double full = 4.0 / 3.0 * kPi * r * r * r;
  // Rounding only: a few ulps of the result.
  EXPECT_NEAR(SphereSlabVolumeM3(1.0, r, -5, 5), full, 1e-14);
  EXPECT_NEAR(SphereSlabVolumeM3(1.0, r, 1.0, 5), full / 2, 1e-14);
  EXPECT_EQ(SphereSlabVolumeM3(1.0, r, 1.4, 5), 0.0);
}

TEST(SphereSlabVolume, MatchesNumericIntegrationForRandomSlabs) {
  scene::SceneRandom random(7);
  for (int k = 0; k < 200; ++k) {
    const double zc = random.Uniform(-1, 1);
    const double r = random.Uniform(0.01, 0.5);
    const double lo = random.Uniform(-1.5, 1.5);
    const double hi = lo + random.Uniform(0, 1);
    // Both are exact for a quadratic cross-section: agreement to rounding (1e-12 of r^3).
    EXPECT_NEAR(SphereSlabVolumeM3(zc, r, lo, hi), SlabBySimpson(zc, r, lo, hi), 1e-12 * r * r * r)
        << zc << " " << r << " " << lo << " " << hi;
  }
}

TEST(DiskRectangleArea, SymmetricCutsGiveSimpleFractions) {
  const double r = 2.0;
  const double disk = kPi * r * r;
  EXPECT_NEAR(DiskRectangleAreaM2(0, 0, r, -5, -5, 5, 5), disk, 1e-12);
  EXPECT_NEAR(DiskRectangleAreaM2(0, 0, r, 0, -5, 5, 5), disk / 2, 1e-12);
  EXPECT_NEAR(DiskRectangleAreaM2(0, 0, r, 0, 0, 5, 5), disk / 4, 1e-12);
  EXPECT_NEAR(DiskRectangleAreaM2(0, 0, r, -5, -5, 0, 0), disk / 4, 1e-12);
  EXPECT_EQ(DiskRectangleAreaM2(0, 0, r, 3, 3, 5, 5), 0.0);
}

TEST(DiskRectangleArea, MatchesNumericIntegrationForRandomRectangles) {
  scene::SceneRandom random(11);
  for (int k = 0; k < 100; ++k) {
    const double cx = random.Uniform(-1, 1);
    const double cy = random.Uniform(-1, 1);
    const double r = random.Uniform(0.1, 1);
    const double x0 = random.Uniform(-2, 1.5);
    const double y0 = random.Uniform(-2, 1.5);
    const double x1 = x0 + random.Uniform(0, 2);
    const double y1 = y0 + random.Uniform(0, 2);
    // See DiskRectangleNumeric: its error is below 1e-7 of the disk area.
    EXPECT_NEAR(DiskRectangleAreaM2(cx, cy, r, x0, y0, x1, y1),
                DiskRectangleNumeric(cx, cy, r, x0, y0, x1, y1), 1e-7 * kPi * r * r)
        << cx << " " << cy << " " << r << " " << x0 << " " << y0 << " " << x1 << " " << y1;
  }
}

Scene LatticeScene(int dimension) {
  Scene scene;
  scene.dimension = dimension;
  scene.container.kind = ContainerKind::kBox;
  scene.container.min_m = {0, 0, 0};
  scene.container.max_m = {1, 1, 1};
  scene.particles.diameter.diameter_m = 0.1;
  scene.measurement.band_min_m = 0.2;
  scene.measurement.band_max_m = 0.6;
  scene.measurement.window_min_m = {0.2, 0.2, 0};
  scene.measurement.window_max_m = {0.8, 0.6, 0};
  return scene;
}

// Touching spheres (disks) on a simple cubic (square) lattice of spacing d filling the box.
ParticleSnapshot Lattice(int dimension) {
  ParticleSnapshot snap;
  snap.dimension = dimension;
  const int nz = dimension == 3 ? 10 : 1;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      for (int k = 0; k < nz; ++k) {
        snap.position_m.push_back(
            {0.05 + 0.1 * i, 0.05 + 0.1 * j, dimension == 3 ? 0.05 + 0.1 * k : 0.0});
        snap.velocity_mps.push_back({0, 0, 0});
        snap.radius_m.push_back(0.05);
        snap.species.push_back(0);
      }
    }
  }
  return snap;
}

TEST(PackingDensity, SimpleCubicLatticeIsPiOverSix) {
  // Band edges fall on lattice planes through particle centres/edges: the slab holds exactly
  // four layers' worth of sphere volume, so only rounding separates it from pi/6.
  EXPECT_NEAR(PackingDensity(Lattice(3), LatticeScene(3)), kPi / 6, 1e-12);
}

TEST(PackingDensity, SquareLatticeOfDisksIsPiOverFour) {
  EXPECT_NEAR(PackingDensity(Lattice(2), LatticeScene(2)), kPi / 4, 1e-12);
}

TEST(CentreCountDensity, CountsWholeParticlesWhoseCentresLieInTheWindow) {
  Scene scene = LatticeScene(2);
  // Edges on lattice-cell boundaries: both estimators see whole cells, so both give pi/4.
  EXPECT_NEAR(CentreCountDensity(Lattice(2), scene), kPi / 4, 1e-12);
  // A 0.32 x 0.32 window from (0.2, 0.2) holds the centres 0.25, 0.35, 0.45 in each direction:
  // 9 whole disks of radius 0.05 over 0.1024; the exact areas add the slivers (0.02 deep) of the
  // next row and column of disks, 0.756 against 0.690.
  scene.measurement.window_max_m = {0.52, 0.52, 0};
  const double count = 9 * kPi * 0.05 * 0.05 / (0.32 * 0.32);
  EXPECT_NEAR(CentreCountDensity(Lattice(2), scene), count, 1e-12);
  EXPECT_GT(PackingDensity(Lattice(2), scene), count + 0.05);
  // 3D: the band 0.2-0.6 holds four layers of centres (0.25..0.55): pi/6 again.
  EXPECT_NEAR(CentreCountDensity(Lattice(3), LatticeScene(3)), kPi / 6, 1e-12);
}

TEST(DensityProfile, SimpleCubicLatticeAveragesToPiOverSixPerLayer) {
  const auto profile = DensityProfileVsHeight(Lattice(3), LatticeScene(3), 0.1);
  // The top may round to one ulp above 1 m and open an eleventh, empty bin.
  ASSERT_GE(profile.density.size(), 10u);
  for (std::size_t b = 0; b < 10; ++b) EXPECT_NEAR(profile.density[b], kPi / 6, 1e-12);
  for (std::size_t b = 10; b < profile.density.size(); ++b)
    EXPECT_NEAR(profile.density[b], 0, 1e-12);
}

TEST(PackingDensity, ParticlesBesideTheContainerDoNotCount) {
  // Spheres that went over the rim and lie on the floor beside the box are not in it: the same
  // lattice plus a copy shifted out of the box leaves every measure unchanged.
  const Scene scene = LatticeScene(3);
  ParticleSnapshot spilled = Lattice(3);
  const ParticleSnapshot inside = Lattice(3);
  for (std::size_t i = 0; i < inside.size(); ++i) {
    spilled.position_m.push_back(
        {inside.position_m[i][0] + 1.5, inside.position_m[i][1], inside.position_m[i][2]});
    spilled.velocity_mps.push_back({0, 0, 0});
    spilled.radius_m.push_back(inside.radius_m[i]);
    spilled.species.push_back(0);
  }
  EXPECT_EQ(PackingDensity(spilled, scene), PackingDensity(inside, scene));
  EXPECT_EQ(CentreCountDensity(spilled, scene), CentreCountDensity(inside, scene));
  EXPECT_EQ(DensityProfileVsHeight(spilled, scene, 0.1).density,
            DensityProfileVsHeight(inside, scene, 0.1).density);
  EXPECT_EQ(Coordination(spilled, scene).mean, Coordination(inside, scene).mean);
}

TEST(DensityProfile, StopsAtTheContainerTopWhateverFliesAboveIt) {
  const Scene scene = LatticeScene(3);  // a 1 m tall box
  ParticleSnapshot snap = Lattice(3);
  snap.position_m.push_back({0.5, 0.5, 1e6});  // flung 1000 km up by a failed run
  snap.velocity_mps.push_back({0, 0, 0});
  snap.radius_m.push_back(0.05);
  snap.species.push_back(0);
  EXPECT_LE(DensityProfileVsHeight(snap, scene, 1e-3).density.size(), 1001u);
}

TEST(Coordination, InteriorOfTouchingLatticesHasFourOrSixNeighbours) {
  // With the tolerance 1.0005 exact lattice neighbours count, diagonals (sqrt 2 d) do not.
  const auto square = Coordination(Lattice(2), LatticeScene(2));
  EXPECT_GT(square.particles, 0);
  EXPECT_DOUBLE_EQ(square.mean, 4.0);
  const auto cubic = Coordination(Lattice(3), LatticeScene(3));
  // The band spans the full box width, so particles on the side walls have 5 or 4 neighbours.
  ASSERT_GE(cubic.histogram.size(), 7u);
  EXPECT_EQ(cubic.histogram[6], 8 * 8 * 4);
  EXPECT_EQ(cubic.particles, 10 * 10 * 4);
}

}  // namespace
}  // namespace bouncecal::dem
