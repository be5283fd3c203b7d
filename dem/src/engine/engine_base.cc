#include <algorithm>
#include <cmath>

#include "engine/engine.h"

namespace bouncecal::dem::scene {

ContactSimd CpuContactSimd() {
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
  // __builtin_cpu_supports also checks that the OS saves the wider registers.
  // The sanitized build has no AVX-512 build (simd_helpers.h).
#if !defined(BOUNCECAL_SCENE_NO_AVX512)
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512vl")) {
    return ContactSimd::kAvx512;
  }
#endif
  if (__builtin_cpu_supports("avx2")) return ContactSimd::kAvx2;
#endif
  return ContactSimd::kBaseline;
}

template <int Dim>
EngineBase<Dim>::EngineBase(const EngineSettings& settings, std::vector<Wall<Dim>> walls)
    : settings_(settings),
      walls_(std::move(walls)),
      pool_(std::make_unique<WorkerPool>(std::max(1, settings.threads))) {}

template <int Dim>
void EngineBase<Dim>::AddParticle(const Vec<Dim>& position_m, const Vec<Dim>& velocity_mps,
                                  double radius_m, double density_kg_per_m3, std::int32_t species) {
  // Inertia, like mass, is that of a sphere in 2D too (see SphereMassKg).
  const double mass = SphereMassKg(density_kg_per_m3, radius_m);
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
  order_.push_back(s.size() - 1);  // the wall history below is in the internal order: appended
  touched_.push_back(0);
  ++untouched_;
  wall_shear_.resize(static_cast<std::size_t>(s.size()) * walls_.size(), Vec<Dim>::Zero());
  wall_normal_history_.resize(wall_shear_.size());
  pairs_valid_ = false;
  forces_valid_ = false;
  DropPendingKick();  // the new particle has no velocity before a kick to continue from
}

template <int Dim>
Vec<Dim> EngineBase<Dim>::Gravity() const {
  Vec<Dim> g = Vec<Dim>::Zero();
  g[Dim - 1] = -settings_.gravity_mps2;
  return g;
}

template <int Dim>
double EngineBase<Dim>::PairReachM(bool van_der_waals) const {
  return skin_m_ + (van_der_waals ? settings_.vdw_cutoff_gap_m : 0.0);
}

template <int Dim>
double EngineBase<Dim>::ChooseSkinM() const {
  const double widest = settings_.skin_m;
  const double narrowest = settings_.min_skin_m;
  if (!(narrowest >= 0 && narrowest < widest)) return widest;
  double speed2 = 0;  // a max, exact in any order: the choice does not depend on the threads
  for (const auto& v : state_.velocity_mps) speed2 = std::max(speed2, v.squaredNorm());
  const double wanted =
      2 * std::sqrt(speed2) * settings_.time_step_s * settings_.skin_rebuild_steps;
  return std::clamp(wanted, narrowest, widest);
}

template <int Dim>
void EngineBase<Dim>::RebuildPairs(bool van_der_waals) {
  skin_m_ = ChooseSkinM();
  const double reach_m = PairReachM(van_der_waals);
  const std::int32_t n = state_.size();
  // from[k]: the internal index before this rebuild of the particle that is now k-th.
  std::vector<std::int32_t> from;
  if (settings_.sort_by_cell && !settings_.brute_force_pairs) {
    from = CellOrder<Dim>(state_.position_m, state_.radius_m, reach_m);
    PermuteParticles(from);
  }
  PairList fresh = settings_.brute_force_pairs
                       ? AllPairs(n)
                       : GridPairs<Dim>(state_.position_m, state_.radius_m, reach_m, pool_.get());
  // Carry the contact history over: the old list is sorted by (first, second), so a pair is
  // found by a binary search among the old pairs of its lower member. A pair whose members
  // swapped order keeps its spring negated (it is the displacement of first relative to second).
  std::vector<Vec<Dim>> shear(fresh.size(), Vec<Dim>::Zero());
  std::vector<NormalHistory> normal(fresh.size());
  const auto old_particles = static_cast<std::int32_t>(pairs_.begin.size()) - 1;
  for (std::size_t p = 0; p < fresh.size(); ++p) {
    std::int32_t a = from.empty() ? fresh.first[p] : from[fresh.first[p]];
    std::int32_t b = from.empty() ? fresh.second[p] : from[fresh.second[p]];
    const bool swapped = a > b;
    if (swapped) std::swap(a, b);
    if (b >= old_particles) continue;  // added since the last rebuild: no history
    const auto lo = pairs_.second.begin() + pairs_.begin[a];
    const auto hi = pairs_.second.begin() + pairs_.begin[a + 1];
    const auto it = std::lower_bound(lo, hi, b);
    if (it == hi || *it != b) continue;
    const auto old = static_cast<std::size_t>(it - pairs_.second.begin());
    shear[p] = swapped ? -pair_shear_[old] : pair_shear_[old];
    normal[p] = pair_normal_history_[old];
  }
  pairs_ = std::move(fresh);
  pair_shear_ = std::move(shear);
  pair_normal_history_ = std::move(normal);
  pair_result_.assign(pairs_.size(), PairResult{Vec<Dim>::Zero(), ZeroSpin<Dim>()});
  pair_live_.assign(pairs_.size(), 1);
  UpdateWallNeighbours();
  position_at_rebuild_ = state_.position_m;
  pairs_valid_ = true;
  ++rebuilds_;
}

template <int Dim>
void EngineBase<Dim>::PermuteParticles(const std::vector<std::int32_t>& from) {
  auto permute = [&](auto& values, std::size_t stride) {
    auto old = values;
    for (std::size_t k = 0; k < from.size(); ++k) {
      const auto source = static_cast<std::size_t>(from[k]);
      for (std::size_t w = 0; w < stride; ++w) values[k * stride + w] = old[source * stride + w];
    }
  };
  auto& s = state_;
  permute(s.position_m, 1);
  permute(s.velocity_mps, 1);
  permute(s.force_n, 1);
  permute(s.angular_velocity_radps, 1);
  permute(s.torque_nm, 1);
  permute(s.radius_m, 1);
  permute(s.mass_kg, 1);
  permute(s.inverse_mass, 1);
  permute(s.inverse_inertia, 1);
  permute(s.species, 1);
  permute(order_, 1);
  permute(wall_shear_, walls_.size());
  permute(wall_normal_history_, walls_.size());
}

template <int Dim>
void EngineBase<Dim>::EnterWorkingOrder() {
  if (working_order_) return;
  working_order_ = true;
  bool identity = true;
  for (std::size_t k = 0; k < order_.size() && identity; ++k)
    identity = static_cast<std::size_t>(order_[k]) == k;
  if (identity) return;
  // PermuteParticles would also move the internal arrays: only the visible state moves here.
  auto& s = state_;
  auto gather = [&](auto& values) {
    auto old = values;
    for (std::size_t k = 0; k < order_.size(); ++k) values[k] = old[order_[k]];
  };
  gather(s.position_m);
  gather(s.velocity_mps);
  gather(s.force_n);
  gather(s.angular_velocity_radps);
  gather(s.torque_nm);
  gather(s.radius_m);
  gather(s.mass_kg);
  gather(s.inverse_mass);
  gather(s.inverse_inertia);
  gather(s.species);
}

template <int Dim>
void EngineBase<Dim>::LeaveWorkingOrder() {
  if (!working_order_) return;
  working_order_ = false;
  auto& s = state_;
  auto scatter = [&](auto& values) {
    auto old = values;
    for (std::size_t k = 0; k < order_.size(); ++k) values[order_[k]] = old[k];
  };
  scatter(s.position_m);
  scatter(s.velocity_mps);
  scatter(s.force_n);
  scatter(s.angular_velocity_radps);
  scatter(s.torque_nm);
  scatter(s.radius_m);
  scatter(s.mass_kg);
  scatter(s.inverse_mass);
  scatter(s.inverse_inertia);
  scatter(s.species);
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
      if (walls_[w].Near(state_.position_m[i], state_.radius_m[i], skin_m_)) {
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
