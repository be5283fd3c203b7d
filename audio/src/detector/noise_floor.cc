#include "detector/noise_floor.h"

#include <algorithm>
#include <cmath>

#include "detector/power_db.h"

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

void NoiseFloor::AddBlock(std::span<const double> powers, double* floors) {
  std::size_t i = 0;
  while (i < powers.size()) {
    bool started = started_;
    double smoothed = smoothed_;
    double current_min = current_min_;
    long long filled = filled_;
    const bool stored = stored_ > 0;
    const double stored_min = stored_min_;
    bool rotate = false;
    for (; i < powers.size() && !rotate; ++i) {
      // As in Add and power().
      const double power = powers[i];
      if (!started) {
        smoothed = power;
        current_min = power;
        started = true;
      } else {
        smoothed += alpha_ * (power - smoothed);
        current_min = std::min(current_min, smoothed);
      }
      rotate = ++filled == subwindow_frames_;
      if (rotate) {
        started_ = started;
        smoothed_ = smoothed;
        current_min_ = current_min;
        filled_ = filled;
        Rotate();
        floors[i] = this->power();
      } else {
        floors[i] = stored ? std::min(current_min, stored_min) : current_min;
      }
    }
    if (!rotate) {
      started_ = started;
      smoothed_ = smoothed;
      current_min_ = current_min;
      filled_ = filled;
    }
  }
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
