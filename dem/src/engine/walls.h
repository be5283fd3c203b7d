#ifndef BOUNCECAL_DEM_ENGINE_WALLS_H_
#define BOUNCECAL_DEM_ENGINE_WALLS_H_

#include <algorithm>
#include <cmath>
#include <vector>

#include "bouncecal/dem/scene.h"
#include "scene/vec.h"

namespace bouncecal::dem::scene {

// One rigid, fixed wall. Particles touch it from one side only; contact geometry is the overlap
// and the unit normal pointing from the wall into the particle (the direction the wall pushes).
template <int Dim>
struct Wall {
  enum class Kind { kPlane, kCylinderSide };
  Kind kind = Kind::kPlane;
  Vec<Dim> point = Vec<Dim>::Zero();   // plane: a point on it; cylinder: on the axis (z ignored)
  Vec<Dim> normal = Vec<Dim>::Zero();  // plane: unit normal into the particles
  double radius_m = 0;                 // cylinder
  double z_min_m = 0;  // cylinder side: a thin shell between these heights, touched from
  double z_max_m = 0;  // inside, outside or over its edges (the rim)

  // True when a particle of radius r at x is closer than margin_m to touching the wall (it may
  // touch it after moving margin_m). Conservative: the cylinder's height limits are widened too.
  bool Near(const Vec<Dim>& x, double r, double margin_m) const {
    if (kind == Kind::kPlane) return r + margin_m - (x - point).dot(normal) > 0;
    if constexpr (Dim == 3) {
      if (x.z() < z_min_m - r - margin_m || x.z() > z_max_m + r + margin_m) {
        return false;
      }
      const double dx = x.x() - point.x();
      const double dy = x.y() - point.y();
      const double inner = radius_m - r - margin_m;
      return !(inner > 0 && dx * dx + dy * dy <= inner * inner);
    }
    return false;
  }

  // Overlap (> 0 in contact) of a particle of radius r at x, and the unit normal into it.
  [[gnu::always_inline]] double Overlap(const Vec<Dim>& x, double r, Vec<Dim>& n) const {
    if (kind == Kind::kPlane) {
      n = normal;
      return r - (x - point).dot(normal);
    }
    if constexpr (Dim == 3) {
      if (x.z() < z_min_m - r || x.z() > z_max_m + r) return -1;
      const double dx = x.x() - point.x();
      const double dy = x.y() - point.y();
      const double rho2 = dx * dx + dy * dy;
      const double inner = radius_m - r;  // no contact while the centre is inside this radius
      if (inner > 0 && rho2 <= inner * inner) return -1;
      const double rho = std::sqrt(rho2);
      if (rho == 0) return -1;
      if (x.z() >= z_min_m && x.z() <= z_max_m && rho <= radius_m) {
        const double overlap = r - (radius_m - rho);
        if (overlap <= 0) return -1;
        n = Vec<Dim>{{-dx / rho, -dy / rho, 0}};
        return overlap;
      }
      // Outside the inner face: the nearest point of the thin shell is on its outer face or on
      // an edge (the rim). Taking the inner face's formula here would read a sphere just outside
      // the wall, or one passing over the rim, as overlapping by up to its diameter and fling
      // it inwards: energy from nothing.
      const double scale = radius_m / rho;
      const double ex = dx - dx * scale;
      const double ey = dy - dy * scale;
      const double ez = x.z() - std::clamp(x.z(), z_min_m, z_max_m);
      const double gap = std::sqrt(ex * ex + ey * ey + ez * ez);
      const double overlap = r - gap;
      if (overlap <= 0 || gap == 0) return -1;
      n = Vec<Dim>{{ex / gap, ey / gap, ez / gap}};
      return overlap;
    }
    return -1;
  }
};

// The walls of a scene's container, in a fixed order (their index keys the contact history).
template <int Dim>
std::vector<Wall<Dim>> ContainerWalls(const ContainerSpec& container);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_WALLS_H_
