#ifndef BOUNCECAL_DEM_SRC_DROP_FLIGHT_H_
#define BOUNCECAL_DEM_SRC_DROP_FLIGHT_H_

#include <cstdint>

#include "drop_state.h"

namespace bouncecal::dem::internal {

struct FlightResult {
  bool landed = false;     // false: max_time_s came first
  double time_s = 0;       // when the lowest point reaches the plane (overlap 0)
  double speed_mps = 0;    // downward speed then
  std::int64_t steps = 0;  // integration steps (0 for a drag-free flight)
};

// Flies the ball from `start` (on or above the plane) until it touches the plane. Without drag
// the flight is a parabola solved in closed form; with quadratic drag it is integrated by RK4
// with steps of at most 1 ms (and 1/64 of the drag-free flight), and the touchdown is located
// on the cubic Hermite interpolant of the last step, so the onset time is not rounded to a step.
FlightResult FlyToPlane(const State& start, const Physics& physics, double max_time_s,
                        TrajectoryRecorder& recorder);

}  // namespace bouncecal::dem::internal

#endif  // BOUNCECAL_DEM_SRC_DROP_FLIGHT_H_
