#include "detector/noise_floor.h"

#include <algorithm>
#include <array>
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

template <std::size_t N>
void NoiseFloor::AddInStep(std::span<NoiseFloor* const> floors,
                           std::span<const std::span<const double>> powers,
                           std::span<double* const> out) {
  const std::size_t count = powers[0].size();
  std::size_t i = 0;
  while (i < count) {
    NoiseFloor& lead = *floors[0];
    // The first frame ever and the frame that completes a sub-window take AddBlock's own path;
    // the frames between them, the same arithmetic here, floor by floor in registers.
    const auto to_rotation = static_cast<std::size_t>(lead.subwindow_frames_ - lead.filled_);
    const std::size_t plain = lead.started_ ? std::min(count - i, to_rotation - 1) : 0;
    std::array<double, N> smoothed, current_min, stored_min;
    std::array<bool, N> stored;
    for (std::size_t f = 0; f < N; ++f) {
      smoothed[f] = floors[f]->smoothed_;
      current_min[f] = floors[f]->current_min_;
      stored[f] = floors[f]->stored_ > 0;
      stored_min[f] = floors[f]->stored_min_;
    }
    for (std::size_t k = i; k < i + plain; ++k) {
      for (std::size_t f = 0; f < N; ++f) {
        smoothed[f] += floors[f]->alpha_ * (powers[f][k] - smoothed[f]);
        current_min[f] = std::min(current_min[f], smoothed[f]);
        out[f][k] = stored[f] ? std::min(current_min[f], stored_min[f]) : current_min[f];
      }
    }
    for (std::size_t f = 0; f < N; ++f) {
      floors[f]->smoothed_ = smoothed[f];
      floors[f]->current_min_ = current_min[f];
      floors[f]->filled_ += static_cast<long long>(plain);
    }
    i += plain;
    if (i < count) {
      for (std::size_t f = 0; f < N; ++f) floors[f]->AddBlock(powers[f].subspan(i, 1), out[f] + i);
      ++i;
    }
  }
}

void NoiseFloor::AddBlocks(std::span<NoiseFloor* const> floors,
                           std::span<const std::span<const double>> powers,
                           std::span<double* const> out) {
  bool in_step = !floors.empty();
  for (std::size_t f = 0; f < floors.size() && in_step; ++f) {
    in_step = powers[f].size() == powers[0].size() &&
              floors[f]->subwindow_frames_ == floors[0]->subwindow_frames_ &&
              floors[f]->filled_ == floors[0]->filled_ &&
              floors[f]->started_ == floors[0]->started_;
  }
  if (in_step && floors.size() == 3) return AddInStep<3>(floors, powers, out);
  if (in_step && floors.size() == 2) return AddInStep<2>(floors, powers, out);
  for (std::size_t f = 0; f < floors.size(); ++f) floors[f]->AddBlock(powers[f], out[f]);
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
