#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/checkpoint_bytes.h"
#include "engine/engine.h"

namespace bouncecal::dem::scene {

// What is not saved is rebuilt from what is: the stepping loop's particle records (loaded from
// state_ at the start of Advance, with the pending velocities of a stopped Advance), the per-chunk
// dense/compacted choice (speed only, same bits) and the wall results (written every step before
// they are read). The pair list is saved as it is, not rebuilt: its order is the order of the force
// sums, hence the last bits.
template <int Dim>
void EngineBase<Dim>::SaveCheckpoint(ByteWriter& out) const {
  const auto& s = state_;
  out.PutVector(s.position_m);
  out.PutVector(s.velocity_mps);
  out.PutVector(s.force_n);
  out.PutVector(s.angular_velocity_radps);
  out.PutVector(s.torque_nm);
  out.PutVector(s.radius_m);
  out.PutVector(s.mass_kg);
  out.PutVector(s.inverse_mass);
  out.PutVector(s.inverse_inertia);
  out.PutVector(s.species);
  out.PutVector(pairs_.first);
  out.PutVector(pairs_.second);
  out.PutVector(pairs_.begin);
  out.PutVector(pairs_.reverse_begin);
  out.PutVector(pairs_.reverse_pairs);
  out.PutVector(pair_shear_);
  out.PutVector(pair_normal_history_);
  out.PutVector(pair_result_);
  out.PutVector(pair_live_);
  out.PutVector(wall_shear_);
  out.PutVector(wall_normal_history_);
  out.PutVector(wall_near_);
  out.PutVector(position_at_rebuild_);
  out.PutVector(order_);
  out.PutVector(touched_);
  out.PutVector(pending_velocity_);
  out.PutVector(pending_spin_);
  out.Put(skin_m_);
  out.Put(static_cast<std::uint8_t>(pairs_valid_));
  out.Put(static_cast<std::uint8_t>(forces_valid_));
  out.Put(steps_);
  out.Put(rebuilds_);
  out.Put(untouched_);
}

template <int Dim>
void EngineBase<Dim>::RestoreCheckpoint(ByteReader& in) {
  auto& s = state_;
  s.position_m = in.GetVector<Vec<Dim>>();
  s.velocity_mps = in.GetVector<Vec<Dim>>();
  s.force_n = in.GetVector<Vec<Dim>>();
  s.angular_velocity_radps = in.GetVector<Spin<Dim>>();
  s.torque_nm = in.GetVector<Spin<Dim>>();
  s.radius_m = in.GetVector<double>();
  s.mass_kg = in.GetVector<double>();
  s.inverse_mass = in.GetVector<double>();
  s.inverse_inertia = in.GetVector<double>();
  s.species = in.GetVector<std::int32_t>();
  pairs_.first = in.GetVector<std::int32_t>();
  pairs_.second = in.GetVector<std::int32_t>();
  pairs_.begin = in.GetVector<std::int32_t>();
  pairs_.reverse_begin = in.GetVector<std::int32_t>();
  pairs_.reverse_pairs = in.GetVector<std::int32_t>();
  pair_shear_ = in.GetVector<Vec<Dim>>();
  pair_normal_history_ = in.GetVector<NormalHistory>();
  pair_result_ = in.GetVector<PairResult>();
  pair_live_ = in.GetVector<std::uint8_t>();
  wall_shear_ = in.GetVector<Vec<Dim>>();
  wall_normal_history_ = in.GetVector<NormalHistory>();
  wall_near_ = in.GetVector<std::uint64_t>();
  position_at_rebuild_ = in.GetVector<Vec<Dim>>();
  order_ = in.GetVector<std::int32_t>();
  touched_ = in.GetVector<std::uint8_t>();
  pending_velocity_ = in.GetVector<Vec<Dim>>();
  pending_spin_ = in.GetVector<Spin<Dim>>();
  skin_m_ = in.Get<double>();
  pairs_valid_ = in.Get<std::uint8_t>() != 0;
  forces_valid_ = in.Get<std::uint8_t>() != 0;
  steps_ = in.Get<std::int64_t>();
  rebuilds_ = in.Get<std::int64_t>();
  untouched_ = in.Get<std::int64_t>();
  working_order_ = false;

  // The checksum already rules out damage; these keep a file that is whole but inconsistent
  // (written by a build with another layout) from indexing out of bounds.
  const std::size_t n = s.position_m.size();
  const std::size_t pairs = pairs_.first.size();
  const std::size_t walls = walls_.size();
  const bool particles_fit =
      s.velocity_mps.size() == n && s.force_n.size() == n && s.angular_velocity_radps.size() == n &&
      s.torque_nm.size() == n && s.radius_m.size() == n && s.mass_kg.size() == n &&
      s.inverse_mass.size() == n && s.inverse_inertia.size() == n && s.species.size() == n &&
      order_.size() == n && touched_.size() == n && wall_shear_.size() == n * walls &&
      wall_normal_history_.size() == n * walls &&
      (pending_velocity_.empty() || (forces_valid_ && pending_velocity_.size() == n)) &&
      pending_spin_.size() == pending_velocity_.size();
  const bool list_fits =
      !pairs_valid_ ||
      (pairs_.second.size() == pairs && pair_shear_.size() == pairs &&
       pair_normal_history_.size() == pairs && pair_result_.size() == pairs &&
       pair_live_.size() == pairs && pairs_.begin.size() == n + 1 &&
       pairs_.reverse_begin.size() == n + 1 && pairs_.reverse_pairs.size() == pairs &&
       wall_near_.size() == n && position_at_rebuild_.size() == n);
  auto below = [](const std::vector<std::int32_t>& v, std::size_t limit) {
    return std::all_of(v.begin(), v.end(), [limit](std::int32_t x) {
      return x >= 0 && static_cast<std::size_t>(x) < limit;
    });
  };
  const bool indices_fit = below(order_, n) && below(pairs_.first, n) && below(pairs_.second, n) &&
                           below(pairs_.begin, pairs + 1) &&
                           below(pairs_.reverse_begin, pairs + 1) &&
                           below(pairs_.reverse_pairs, std::max<std::size_t>(pairs, 1));
  if (!particles_fit || !list_fits || !indices_fit || steps_ < 0) {
    in.Fail("its engine state does not fit together");
  }
}

template void EngineBase<2>::SaveCheckpoint(ByteWriter&) const;
template void EngineBase<3>::SaveCheckpoint(ByteWriter&) const;
template void EngineBase<2>::RestoreCheckpoint(ByteReader&);
template void EngineBase<3>::RestoreCheckpoint(ByteReader&);

}  // namespace bouncecal::dem::scene
