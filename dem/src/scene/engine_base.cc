#include <algorithm>
#include <cmath>

#include "scene/engine.h"

namespace bouncecal::dem::scene {

template <int Dim>
EngineBase<Dim>::EngineBase(const EngineSettings& settings, std::vector<Wall<Dim>> walls)
    : settings_(settings),
      walls_(std::move(walls)),
      pool_(std::make_unique<WorkerPool>(std::max(1, settings.threads))) {}

template <int Dim>
void EngineBase<Dim>::AddParticle(const Vec<Dim>& position_m, const Vec<Dim>& velocity_mps,
                                  double radius_m, double density_kg_per_m3, std::int32_t species) {
  // Spheres in 3D; in 2D the particles are spheres whose centres move in a plane (paper 004
  // packs spheres in a monolayer), so mass and inertia are those of a sphere in both cases.
  constexpr double kPi = 3.14159265358979323846;
  const double mass = density_kg_per_m3 * 4.0 / 3.0 * kPi * radius_m * radius_m * radius_m;
  auto& s = state_;
  s.position_m.push_back(position_m);
  s.velocity_mps.push_back(velocity_mps);
  s.force_n.push_back(mass * Gravity());
  s.angular_velocity_radps.push_back(ZeroSpin<Dim>());
  s.torque_nm.push_back(ZeroSpin<Dim>());
  s.radius_m.push_back(radius_m);
  s.mass_kg.push_back(mass);
  s.inverse_mass.push_back(1.0 / mass);
  s.inverse_inertia.push_back(1.0 / (0.4 * mass * radius_m * radius_m));
  s.species.push_back(species);
  wall_shear_.resize(static_cast<std::size_t>(s.size()) * walls_.size(), Vec<Dim>::Zero());
  wall_normal_history_.resize(wall_shear_.size());
  pairs_valid_ = false;
  forces_valid_ = false;
}

template <int Dim>
Vec<Dim> EngineBase<Dim>::Gravity() const {
  Vec<Dim> g = Vec<Dim>::Zero();
  g[Dim - 1] = -settings_.gravity_mps2;
  return g;
}

template <int Dim>
double EngineBase<Dim>::PairReachM(bool van_der_waals) const {
  return settings_.skin_m + (van_der_waals ? settings_.vdw_cutoff_gap_m : 0.0);
}

template <int Dim>
void EngineBase<Dim>::RebuildPairs(double reach_m) {
  const std::int32_t n = state_.size();
  PairList fresh = settings_.brute_force_pairs
                       ? AllPairs(n)
                       : GridPairs<Dim>(state_.position_m, state_.radius_m, reach_m);
  // Both lists are sorted by (first, second): one merge walk carries the contact history over.
  std::vector<Vec<Dim>> shear(fresh.size(), Vec<Dim>::Zero());
  std::vector<NormalHistory> normal(fresh.size());
  std::size_t old = 0;
  for (std::size_t p = 0; p < fresh.size() && old < pairs_.size(); ++p) {
    while (old < pairs_.size() &&
           (pairs_.first[old] < fresh.first[p] ||
            (pairs_.first[old] == fresh.first[p] && pairs_.second[old] < fresh.second[p]))) {
      ++old;
    }
    if (old < pairs_.size() && pairs_.first[old] == fresh.first[p] &&
        pairs_.second[old] == fresh.second[p]) {
      shear[p] = pair_shear_[old];
      normal[p] = pair_normal_history_[old];
    }
  }
  pairs_ = std::move(fresh);
  pair_shear_ = std::move(shear);
  pair_normal_history_ = std::move(normal);
  pair_result_.assign(pairs_.size(), PairResult{Vec<Dim>::Zero(), ZeroSpin<Dim>()});
  chunk_contacts_.resize(static_cast<std::size_t>(pool_->threads()));
  for (auto& contacts : chunk_contacts_) contacts.resize(pairs_.size());
  UpdateWallNeighbours();
  position_at_rebuild_ = state_.position_m;
  pairs_valid_ = true;
  ++rebuilds_;
}

template <int Dim>
void EngineBase<Dim>::UpdateWallNeighbours() {
  const std::size_t n = static_cast<std::size_t>(state_.size());
  const std::size_t wall_count = walls_.size();
  wall_near_.assign(n, 0);
  // The brute-force path never rebuilds, and more than 64 walls do not fit the mask: every
  // wall is then checked every step.
  const bool all = settings_.brute_force_pairs || wall_count > 64;
  for (std::size_t i = 0; i < n; ++i) {
    if (all) {
      wall_near_[i] = ~std::uint64_t{0};
      continue;
    }
    for (std::size_t w = 0; w < wall_count; ++w) {
      // A particle moves at most skin/2 before the next rebuild, so one farther than the skin
      // cannot reach the wall before then; its history is zero and stays so.
      if (walls_[w].Near(state_.position_m[i], state_.radius_m[i], settings_.skin_m)) {
        wall_near_[i] |= std::uint64_t{1} << w;
      } else {
        wall_shear_[i * wall_count + w] = Vec<Dim>::Zero();
        wall_normal_history_[i * wall_count + w] = NormalHistory{};
      }
    }
  }
}

template <int Dim>
double EngineBase<Dim>::KineticEnergyJ() const {
  // Serial and in index order, so the figure is identical for every thread count.
  double energy = 0;
  const auto& s = state_;
  for (std::int32_t i = 0; i < s.size(); ++i) {
    energy += 0.5 * s.mass_kg[i] * s.velocity_mps[i].squaredNorm();
    energy += 0.5 / s.inverse_inertia[i] * SpinSquaredNorm(s.angular_velocity_radps[i]);
  }
  return energy;
}

template <int Dim>
bool EngineBase<Dim>::HasNonFiniteState() const {
  for (std::int32_t i = 0; i < state_.size(); ++i) {
    if (!state_.position_m[i].allFinite() || !state_.velocity_mps[i].allFinite()) return true;
  }
  return false;
}

template <int Dim>
std::vector<Wall<Dim>> ContainerWalls(const ContainerSpec& c) {
  std::vector<Wall<Dim>> walls;
  auto plane = [&](const Vec3& point, const Vec3& normal) {
    Wall<Dim> wall;
    wall.kind = Wall<Dim>::Kind::kPlane;
    double norm = 0;
    for (int d = 0; d < Dim; ++d) norm += normal[d] * normal[d];
    norm = std::sqrt(norm);
    for (int d = 0; d < Dim; ++d) {
      wall.point[d] = point[d];
      wall.normal[d] = normal[d] / norm;
    }
    walls.push_back(wall);
  };
  switch (c.kind) {
    case ContainerKind::kPlane:
      plane(c.point_m, c.normal);
      break;
    case ContainerKind::kCylinder: {
      Vec3 up{0, 0, 0};
      up[Dim - 1] = 1;
      plane(c.center_m, up);
      if constexpr (Dim == 3) {
        Wall<Dim> side;
        side.kind = Wall<Dim>::Kind::kCylinderSide;
        side.point = Vec<Dim>{{c.center_m[0], c.center_m[1], c.center_m[2]}};
        side.radius_m = c.radius_m;
        side.z_min_m = c.center_m[2];
        side.z_max_m = c.center_m[2] + c.height_m;
        walls.push_back(side);
      }
      break;
    }
    case ContainerKind::kBox:
      for (int d = Dim - 1; d >= 0; --d) {
        Vec3 normal{0, 0, 0};
        normal[d] = 1;
        plane(c.min_m, normal);  // floor first, then the side walls
        if (d == Dim - 1 && !c.closed_top) continue;
        normal[d] = -1;
        plane(c.max_m, normal);
      }
      break;
  }
  return walls;
}

template class EngineBase<2>;
template class EngineBase<3>;
template std::vector<Wall<2>> ContainerWalls<2>(const ContainerSpec&);
template std::vector<Wall<3>> ContainerWalls<3>(const ContainerSpec&);

}  // namespace bouncecal::dem::scene
