#include "drop_flight.h"

#include <algorithm>
#include <cmath>

namespace bouncecal::dem::internal {
namespace {

double FlightAcceleration(const Physics& physics, double v) {
  return -physics.gravity_mps2 - physics.drag_per_mass * v * std::abs(v);
}

// Cubic Hermite interpolant on [0, h] through (z0, v0) and (z1, v1): value and slope at s.
struct Hermite {
  double z0, v0, z1, v1, h;
  double Value(double s) const {
    const double u = s / h, u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * z0 + (u3 - 2 * u2 + u) * h * v0 + (-2 * u3 + 3 * u2) * z1 +
           (u3 - u2) * h * v1;
  }
  double Slope(double s) const {
    const double u = s / h, u2 = u * u;
    return ((6 * u2 - 6 * u) * z0 + (6 * u2 - 6 * u) * -z1) / h + (3 * u2 - 4 * u + 1) * v0 +
           (3 * u2 - 2 * u) * v1;
  }
};

}  // namespace

FlightResult FlyToPlane(const State& start, const Physics& physics, double max_time_s,
                        TrajectoryRecorder& recorder) {
  const double g = physics.gravity_mps2;
  const double z0 = std::max(start.z, 0.0);
  FlightResult result;
  if (physics.drag_per_mass == 0) {
    result.speed_mps = std::sqrt(start.v * start.v + 2 * g * z0);
    result.time_s = start.t + (start.v + result.speed_mps) / g;
    result.landed = result.time_s <= max_time_s;
    recorder.Ballistic(start.t, z0, start.v, g, std::min(result.time_s, max_time_s));
    return result;
  }
  const double free_flight = (start.v + std::sqrt(start.v * start.v + 2 * g * z0)) / g;
  const double h = std::clamp(free_flight / 64, 1e-12, 1e-3);
  double t = start.t, z = z0, v = start.v;
  for (;;) {
    const double k1z = v, k1v = FlightAcceleration(physics, v);
    const double k2z = v + 0.5 * h * k1v, k2v = FlightAcceleration(physics, k2z);
    const double k3z = v + 0.5 * h * k2v, k3v = FlightAcceleration(physics, k3z);
    const double k4z = v + h * k3v, k4v = FlightAcceleration(physics, k4z);
    const double z1 = z + h / 6 * (k1z + 2 * k2z + 2 * k3z + k4z);
    const double v1 = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    ++result.steps;
    if (z1 < 0 && v1 < 0) {
      const Hermite cubic{z, v, z1, v1, h};
      double lo = 0, hi = h;  // cubic(lo) >= 0 > cubic(hi) while falling
      for (int i = 0; i < 60 && hi - lo > 1e-15 * (t + h); ++i) {
        const double mid = 0.5 * (lo + hi);
        (cubic.Value(mid) >= 0 ? lo : hi) = mid;
      }
      const double s = 0.5 * (lo + hi);
      result.time_s = t + s;
      result.speed_mps = -cubic.Slope(s);
      result.landed = result.time_s <= max_time_s;
      recorder.Segment(t, z, v, std::min(t + s, max_time_s), 0, -result.speed_mps);
      return result;
    }
    recorder.Segment(t, z, v, t + h, z1, v1);
    t += h;
    z = z1;
    v = v1;
    if (t > max_time_s) return result;
  }
}

}  // namespace bouncecal::dem::internal
