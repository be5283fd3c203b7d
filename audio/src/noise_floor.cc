#include "noise_floor.h"

#include <algorithm>
#include <cmath>

#include "power_db.h"

namespace bouncecal::audio {

NoiseFloor::NoiseFloor(double frame_s, double smoothing_s, double window_s, int subwindows)
    : alpha_(std::min(1.0, frame_s / smoothing_s)),
      subwindow_frames_(std::max(1LL, std::llround(window_s / subwindows / frame_s))),
      minima_(static_cast<std::size_t>(subwindows), 0.0) {}

void NoiseFloor::Rotate() {
  minima_[next_] = current_min_;
  next_ = (next_ + 1) % minima_.size();
  stored_ = std::min(stored_ + 1, minima_.size());
  stored_min_ = minima_[0];
  for (std::size_t i = 1; i < stored_; ++i) stored_min_ = std::min(stored_min_, minima_[i]);
  filled_ = 0;
  current_min_ = smoothed_;
}

double NoiseFloor::db() const {
  const double floor = power();
  // The detector asks every frame; the floor changes far less often.
  if (floor != cached_floor_) {
    cached_floor_ = floor;
    cached_db_ = ToDb(floor);
  }
  return cached_db_;
}

double NoiseFloor::ToDb(double power) { return PowerToDb(std::max(power, 1e-14)); }

}  // namespace bouncecal::audio
