#ifndef BOUNCECAL_DEM_ENGINE_ENGINE_WALLS_H_
#define BOUNCECAL_DEM_ENGINE_ENGINE_WALLS_H_

// The packing engine's particle-wall contacts. A wall is a rigid body of infinite mass and
// curvature radius (m_eff = m, R_eff = r); its contacts run through the same contact stages as
// the pairs, with the normal and overlap from the wall's geometry (walls.h) instead of a centre
// distance. Each (particle, wall) slot keeps its own result, spring and normal history; only the
// walls a particle was near at the last rebuild are visited. Members of Engine, defined here and
// included by engine_impl.h after the class (same translation unit as the rest of the step).

#include <cstddef>
#include <cstdint>

#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

// The wall contacts of particles [begin, end) (the pair-pass chunk's share): a touching one goes
// into a block of t, run through the stages' wall build by WallBlock; a slot that does not touch
// is cleared.
template <int Dim, class Law, class Phys>
inline void Engine<Dim, Law, Phys>::WallRange(Scratch& t, std::int64_t begin, std::int64_t end) {
  const std::size_t wall_count = this->walls_.size();
  int count = 0;
  for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
    const std::uint64_t near = this->wall_near_[i];
    if (near == 0 && wall_count <= 64) continue;
    const Record& record = records_[i];
    const double r_i = record.position_radius.s;
    for (std::size_t w = 0; w < wall_count; ++w) {
      if (w < 64 && ((near >> w) & 1) == 0) continue;
      const std::size_t h = i * wall_count + w;
      V n;
      const double overlap = this->walls_[w].Overlap(record.position_radius.v, r_i, n);
      if (overlap <= 0) {
        wall_result_[h] = {V::Zero(), ZeroSpin<Dim>()};
        if constexpr (Phys::kTangential) this->wall_shear_[h] = V::Zero();
        if constexpr (Law::kNeedsHistory) this->wall_normal_history_[h] = NormalHistory{};
        continue;
      }
      t.pair[count] = static_cast<std::int32_t>(h);
      t.overlap[count] = overlap;
      t.radius_i[count] = r_i;
      t.mass_i[count] = record.velocity_mass.s;
      for (int c = 0; c < Dim; ++c) {
        t.normal[c][count] = n[c];
        t.velocity[c][count] = record.velocity_mass.v[c];
      }
      if constexpr (Phys::kRotation) {
        if constexpr (Dim == 3) {
          for (int c = 0; c < 3; ++c) t.spin[c][count] = r_i * record.spin_inertia.w[c];
        } else {
          t.spin[0][count] = r_i * record.spin_inertia.w;
        }
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) t.shear[c][count] = this->wall_shear_[h][c];
      }
      if (++count == kBlock) {
        WallBlock(kBlock, t);
        count = 0;
      }
    }
  }
  if (count > 0) WallBlock(count, t);
}

// The wall contacts of block t: arithmetic, then each slot's result and spring written back.
template <int Dim, class Law, class Phys>
inline void Engine<Dim, Law, Phys>::WallBlock(int n, Scratch& t) {
  stages_.template Run<true>(simd_, t, n, this->wall_normal_history_);
  for (int k = 0; k < n; ++k) {
    const auto h = static_cast<std::size_t>(t.pair[k]);
    auto& result = wall_result_[h];
    for (int c = 0; c < Dim; ++c) result.force_n[c] = t.force[c][k];
    if constexpr (Phys::kRotation) {
      if constexpr (Dim == 3) {
        for (int c = 0; c < 3; ++c) result.twist_n[c] = t.twist[c][k];
      } else {
        result.twist_n = t.twist[0][k];
      }
    }
    if constexpr (Phys::kTangential) {
      for (int c = 0; c < Dim; ++c) this->wall_shear_[h][c] = t.shear[c][k];
    }
  }
}

// Particle i's wall forces and twists added to its sums: the walls it was near at the last
// rebuild (with more than 64 walls, every wall from the 65th on), whose results WallRange wrote
// this step.
template <int Dim, class Law, class Phys>
[[gnu::always_inline]] inline void Engine<Dim, Law, Phys>::AddWallLoads(std::int32_t i, V& force,
                                                                        S& twist) const {
  const std::size_t wall_count = this->walls_.size();
  const std::uint64_t near = this->wall_near_[static_cast<std::size_t>(i)];
  for (std::size_t w = 0; w < wall_count; ++w) {
    if (w >= 64 || ((near >> w) & 1) != 0) {
      const PairResult& wall = wall_result_[static_cast<std::size_t>(i) * wall_count + w];
      force += wall.force_n;
      if constexpr (Phys::kRotation) twist += wall.twist_n;
    }
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_ENGINE_WALLS_H_
