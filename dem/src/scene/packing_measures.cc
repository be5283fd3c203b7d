#include "bouncecal/dem/packing_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "bouncecal/error.h"
#include "scene/pair_list.h"

namespace bouncecal::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Integral of sqrt(r^2 - x^2) from 0 to x.
double HalfChordIntegral(double x, double r) {
  const double u = std::clamp(x / r, -1.0, 1.0);
  return 0.5 * r * r * (u * std::sqrt(std::max(0.0, 1 - u * u)) + std::asin(u));
}

// Area of the disk (centre at the origin) with x <= a and y <= b: the integral over x of the
// part of the chord [-s(x), s(x)] below b, which is b + s inside |x| <= sqrt(r^2 - b^2) and
// either the whole chord (b > 0) or nothing (b < 0) outside.
double QuadrantArea(double a, double b, double r) {
  if (a <= -r || b <= -r) return 0;
  const double x_end = std::min(a, r);
  auto s_int = [r](double x) { return HalfChordIntegral(x, r); };
  if (b >= r) return 2 * (s_int(x_end) - s_int(-r));
  const double c = std::sqrt(r * r - b * b);
  double area = 0;
  if (b > 0) area += 2 * (s_int(std::min(x_end, -c)) - s_int(-r));
  if (x_end > -c) {
    const double x2 = std::min(x_end, c);
    area += b * (x2 + c) + s_int(x2) - s_int(-c);
  }
  if (b > 0 && x_end > c) area += 2 * (s_int(x_end) - s_int(c));
  return area;
}

std::string Where(const Scene& scene) {
  return scene.source.empty() ? std::string("scene") : scene.source.string();
}

template <int Dim>
std::vector<scene::Vec<Dim>> ToVec(const ParticleSnapshot& snapshot) {
  std::vector<scene::Vec<Dim>> out(snapshot.size());
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    for (int d = 0; d < Dim; ++d) out[i][d] = snapshot.position_m[i][d];
  }
  return out;
}

// 3D: whether a centre lies over the container's floor area (inside the cylinder or the box's
// sides). The walls keep the particles poured in there; one that went over the rim and lies
// beside the container must not count towards its density. 2D measures in an explicit window.
bool InsideFootprint(const Vec3& x, const Scene& scene) {
  const auto& c = scene.container;
  if (scene.dimension != 3) return true;
  switch (c.kind) {
    case ContainerKind::kCylinder: {
      const double dx = x[0] - c.center_m[0];
      const double dy = x[1] - c.center_m[1];
      return dx * dx + dy * dy <= c.radius_m * c.radius_m;
    }
    case ContainerKind::kBox:
      return x[0] >= c.min_m[0] && x[0] <= c.max_m[0] && x[1] >= c.min_m[1] && x[1] <= c.max_m[1];
    case ContainerKind::kPlane:
      break;
  }
  return true;
}

bool InMeasurementRegion(const Vec3& x, const Scene& scene) {
  const auto& m = scene.measurement;
  if (scene.dimension == 3) {
    return x[2] >= m.band_min_m && x[2] <= m.band_max_m && InsideFootprint(x, scene);
  }
  return x[0] >= m.window_min_m[0] && x[0] <= m.window_max_m[0] && x[1] >= m.window_min_m[1] &&
         x[1] <= m.window_max_m[1];
}

}  // namespace

double SphereSlabVolumeM3(double center_z_m, double radius_m, double z_lo_m, double z_hi_m) {
  const double lo = std::clamp(z_lo_m - center_z_m, -radius_m, radius_m);
  const double hi = std::clamp(z_hi_m - center_z_m, -radius_m, radius_m);
  if (hi <= lo) return 0;
  const double r2 = radius_m * radius_m;
  return kPi * ((r2 * hi - hi * hi * hi / 3) - (r2 * lo - lo * lo * lo / 3));
}

double DiskRectangleAreaM2(double center_x_m, double center_y_m, double radius_m, double x_lo_m,
                           double y_lo_m, double x_hi_m, double y_hi_m) {
  if (x_hi_m <= x_lo_m || y_hi_m <= y_lo_m || radius_m <= 0) return 0;
  const double x0 = x_lo_m - center_x_m;
  const double x1 = x_hi_m - center_x_m;
  const double y0 = y_lo_m - center_y_m;
  const double y1 = y_hi_m - center_y_m;
  const double r = radius_m;
  const double area = QuadrantArea(x1, y1, r) - QuadrantArea(x0, y1, r) - QuadrantArea(x1, y0, r) +
                      QuadrantArea(x0, y0, r);
  return std::clamp(area, 0.0, kPi * r * r);
}

double ContainerFloorM(const Scene& scene) {
  const auto& c = scene.container;
  const int up = scene.dimension - 1;
  switch (c.kind) {
    case ContainerKind::kCylinder:
      return c.center_m[up];
    case ContainerKind::kBox:
      return c.min_m[up];
    case ContainerKind::kPlane:
      return c.point_m[up];
  }
  return 0;
}

double ContainerTopM(const Scene& scene) {
  const auto& c = scene.container;
  const int up = scene.dimension - 1;
  switch (c.kind) {
    case ContainerKind::kCylinder:
      return c.center_m[up] + c.height_m;
    case ContainerKind::kBox:
      return c.max_m[up];
    case ContainerKind::kPlane:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

double ContainerCrossSection(const Scene& scene) {
  const auto& c = scene.container;
  switch (c.kind) {
    case ContainerKind::kCylinder:
      return scene.dimension == 3 ? kPi * c.radius_m * c.radius_m : 2 * c.radius_m;
    case ContainerKind::kBox:
      return scene.dimension == 3 ? (c.max_m[0] - c.min_m[0]) * (c.max_m[1] - c.min_m[1])
                                  : (c.max_m[0] - c.min_m[0]);
    case ContainerKind::kPlane:
      break;
  }
  throw ConfigError(Where(scene) +
                    ": container: a lone plane has no cross-section to measure a packing "
                    "density over; use a cylinder or box container");
}

double PackingDensity(const ParticleSnapshot& snapshot, const Scene& scene) {
  const auto& m = scene.measurement;
  double solid = 0;
  if (scene.dimension == 3) {
    const double height = m.band_max_m - m.band_min_m;
    if (!(height > 0)) {
      throw ConfigError(Where(scene) +
                        ": measurement.band_m is empty; give [low, high] heights in m");
    }
    for (std::size_t i = 0; i < snapshot.size(); ++i) {
      if (!InsideFootprint(snapshot.position_m[i], scene)) continue;
      solid += SphereSlabVolumeM3(snapshot.position_m[i][2], snapshot.radius_m[i], m.band_min_m,
                                  m.band_max_m);
    }
    return solid / (ContainerCrossSection(scene) * height);
  }
  const double area =
      (m.window_max_m[0] - m.window_min_m[0]) * (m.window_max_m[1] - m.window_min_m[1]);
  if (!(area > 0)) {
    throw ConfigError(Where(scene) +
                      ": measurement.window is empty; give min_m and max_m corners in m");
  }
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    solid += DiskRectangleAreaM2(snapshot.position_m[i][0], snapshot.position_m[i][1],
                                 snapshot.radius_m[i], m.window_min_m[0], m.window_min_m[1],
                                 m.window_max_m[0], m.window_max_m[1]);
  }
  return solid / area;
}

double CentreCountDensity(const ParticleSnapshot& snapshot, const Scene& scene) {
  const auto& m = scene.measurement;
  const double region =
      scene.dimension == 3
          ? (m.band_max_m - m.band_min_m) * ContainerCrossSection(scene)
          : (m.window_max_m[0] - m.window_min_m[0]) * (m.window_max_m[1] - m.window_min_m[1]);
  if (!(region > 0)) {
    throw ConfigError(Where(scene) + (scene.dimension == 3
                                          ? ": measurement.band_m is empty; give [low, high] "
                                            "heights in m"
                                          : ": measurement.window is empty; give min_m and max_m "
                                            "corners in m"));
  }
  double solid = 0;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    if (!InMeasurementRegion(snapshot.position_m[i], scene)) continue;
    const double r = snapshot.radius_m[i];
    solid += scene.dimension == 3 ? 4.0 / 3.0 * kPi * r * r * r : kPi * r * r;
  }
  return solid / region;
}

DensityProfile DensityProfileVsHeight(const ParticleSnapshot& snapshot, const Scene& scene,
                                      double bin_m) {
  if (!(bin_m > 0)) throw ConfigError(Where(scene) + ": profile bin must be > 0 m");
  const double cross = ContainerCrossSection(scene);
  const int up = scene.dimension - 1;
  const double floor = ContainerFloorM(scene);
  double top = floor;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    top = std::max(top, snapshot.position_m[i][up] + snapshot.radius_m[i]);
  }
  // The profile is of the container: a particle flung far above it (or out over its rim) would
  // otherwise stretch the table to millions of empty rows.
  top = std::min(top, ContainerTopM(scene));
  // and kMaxProfileBins bounds it where nothing above does (a lone plane; RunPacking refuses a
  // bin that cuts a container into more before running).
  const double span_bins = std::min(std::ceil((top - floor) / bin_m), kMaxProfileBins);
  const auto bins = static_cast<std::size_t>(std::max(span_bins, 0.0));
  DensityProfile profile;
  profile.height_m.resize(bins);
  profile.density.assign(bins, 0.0);
  for (std::size_t b = 0; b < bins; ++b) profile.height_m[b] = floor + (b + 0.5) * bin_m;
  const auto& c = scene.container;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    if (!InsideFootprint(snapshot.position_m[i], scene)) continue;
    const double z = snapshot.position_m[i][up];
    const double r = snapshot.radius_m[i];
    const auto first = static_cast<std::int64_t>(std::floor((z - r - floor) / bin_m));
    const auto last = static_cast<std::int64_t>(std::floor((z + r - floor) / bin_m));
    for (std::int64_t b = std::max<std::int64_t>(first, 0);
         b <= last && b < static_cast<std::int64_t>(bins); ++b) {
      const double lo = floor + static_cast<double>(b) * bin_m;
      const double hi = lo + bin_m;
      if (scene.dimension == 3) {
        profile.density[b] += SphereSlabVolumeM3(z, r, lo, hi);
      } else {
        const double x_lo = c.kind == ContainerKind::kBox ? c.min_m[0] : -1e300;
        const double x_hi = c.kind == ContainerKind::kBox ? c.max_m[0] : 1e300;
        profile.density[b] +=
            DiskRectangleAreaM2(snapshot.position_m[i][0], z, r, x_lo, lo, x_hi, hi);
      }
    }
  }
  for (double& d : profile.density) d /= cross * bin_m;
  return profile;
}

CoordinationStats Coordination(const ParticleSnapshot& snapshot, const Scene& scene) {
  const double tolerance = scene.measurement.contact_tolerance;
  double r_max = 0;
  for (double r : snapshot.radius_m) r_max = std::max(r_max, r);
  const double reach = (tolerance - 1) * 2 * r_max;
  const auto n = static_cast<std::int32_t>(snapshot.size());
  scene::PairList pairs = scene.dimension == 3
                              ? scene::GridPairs<3>(ToVec<3>(snapshot), snapshot.radius_m, reach)
                              : scene::GridPairs<2>(ToVec<2>(snapshot), snapshot.radius_m, reach);
  std::vector<std::int32_t> count(static_cast<std::size_t>(n), 0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const std::int32_t i = pairs.first[p];
    const std::int32_t j = pairs.second[p];
    double dist2 = 0;
    for (int d = 0; d < 3; ++d) {
      const double delta = snapshot.position_m[i][d] - snapshot.position_m[j][d];
      dist2 += delta * delta;
    }
    const double touch = tolerance * (snapshot.radius_m[i] + snapshot.radius_m[j]);
    if (dist2 < touch * touch) {
      ++count[i];
      ++count[j];
    }
  }
  CoordinationStats stats;
  std::int64_t sum = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    if (!InMeasurementRegion(snapshot.position_m[i], scene)) continue;
    const auto z = static_cast<std::size_t>(count[i]);
    if (stats.histogram.size() <= z) stats.histogram.resize(z + 1, 0);
    ++stats.histogram[z];
    ++stats.particles;
    sum += count[i];
  }
  stats.mean = stats.particles > 0 ? static_cast<double>(sum) / stats.particles : 0.0;
  return stats;
}

}  // namespace bouncecal::dem
