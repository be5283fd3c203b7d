// Paper 004's "velocity set to zero at the first collision" (Cheng, Guo & Lai 1999, section 2:
// "颗粒发生首次碰撞，令其速度为零", and section 3.1). The paper states it as part of its method,
// next to local damping, to shorten the time to a steady packing: a particle's fall energy is
// removed when it first lands, instead of being dissipated by many damped bounces. It applies
// once per particle; later collisions follow the contact laws.

#include "engine/engine.h"

namespace bouncecal::dem::scene {

template <int Dim>
void EngineBase<Dim>::StopFirstContacts() {
  if (untouched_ == 0) return;
  auto& s = state_;
  auto stop = [&](std::int32_t i) {
    auto& touched = touched_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
    if (touched != 0) return;
    touched = 1;
    --untouched_;
    s.velocity_mps[i] = Vec<Dim>::Zero();
    s.angular_velocity_radps[i] = ZeroSpin<Dim>();
  };
  auto is_touched = [&](std::int32_t i) {
    return touched_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])] != 0;
  };
  // Every pair that can overlap is listed (the list reaches r_i + r_j + skin). Both members of
  // an overlapping pair are tested before either is stopped, so the result does not depend on
  // the order of the list.
  std::vector<std::int32_t> hits;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const std::int32_t i = pairs_.first[p];
    const std::int32_t j = pairs_.second[p];
    if (is_touched(i) && is_touched(j)) continue;
    const double reach = s.radius_m[i] + s.radius_m[j];
    if ((s.position_m[i] - s.position_m[j]).squaredNorm() < reach * reach) {
      hits.push_back(i);
      hits.push_back(j);
    }
  }
  const std::int32_t n = s.size();
  for (std::int32_t i = 0; i < n; ++i) {
    if (is_touched(i)) continue;
    Vec<Dim> normal;
    for (const auto& wall : walls_) {
      if (wall.Overlap(s.position_m[i], s.radius_m[i], normal) > 0) {
        hits.push_back(i);
        break;
      }
    }
  }
  for (std::int32_t i : hits) stop(i);
}

template void EngineBase<2>::StopFirstContacts();
template void EngineBase<3>::StopFirstContacts();

}  // namespace bouncecal::dem::scene
