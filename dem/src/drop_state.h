#ifndef BOUNCECAL_DEM_SRC_DROP_STATE_H_
#define BOUNCECAL_DEM_SRC_DROP_STATE_H_

#include <vector>

#include "bouncecal/dem/drop.h"

namespace bouncecal::dem::internal {

struct Physics {
  double mass_kg;
  double radius_m;
  double gravity_mps2;
  double drag_per_mass;  // (1/2) rho C_d A / m, 0 without drag
};

// Records z(t) at a fixed interval from the states the integrator visits.
class TrajectoryRecorder {
 public:
  TrajectoryRecorder(double interval_s, std::vector<TrajectoryPoint>* out)
      : interval_(interval_s), out_(out) {}
  bool enabled() const { return interval_ > 0; }
  double next_time() const { return next_; }
  void Add(double time_s, double height_m, double velocity_mps) {
    out_->push_back({time_s, height_m, velocity_mps});
    next_ = interval_ * static_cast<double>(out_->size());
  }
  // Linear interpolation between two consecutive integrator states (used inside contacts,
  // where steps are far shorter than any useful interval).
  void Segment(double t0, double z0, double v0, double t1, double z1, double v1) {
    if (!enabled()) return;
    while (next_ <= t1) {
      const double w = t1 > t0 ? (next_ - t0) / (t1 - t0) : 1;
      Add(next_, z0 + w * (z1 - z0), v0 + w * (v1 - v0));
    }
  }
  // A drag-free flight from (t0, z0, v0) up to t_end: exact parabola.
  void Ballistic(double t0, double z0, double v0, double g, double t_end) {
    if (!enabled()) return;
    while (next_ <= t_end) {
      const double s = next_ - t0;
      Add(next_, z0 + v0 * s - 0.5 * g * s * s, v0 - g * s);
    }
  }

 private:
  double interval_;
  std::vector<TrajectoryPoint>* out_;
  double next_ = 0;
};

struct State {
  double t = 0;
  double z = 0;  // height of the lowest point; overlap = -z
  double v = 0;  // upward
};

}  // namespace bouncecal::dem::internal

#endif  // BOUNCECAL_DEM_SRC_DROP_STATE_H_
