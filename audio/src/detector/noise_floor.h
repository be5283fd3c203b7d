#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_NOISE_FLOOR_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_NOISE_FLOOR_H_

#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace bouncecal::audio {

// Noise floor of an energy envelope by minimum statistics (R. Martin, IEEE Trans. Speech Audio
// Process. 9(5), 2001): the minimum of the smoothed power over a sliding window of a few
// seconds, kept as the minima of sub-windows so memory is fixed. Impacts and their tails are
// short compared with the window, so the minimum tracks the background even in a busy
// sequence; it sits a little (1-2 dB) below the mean noise power, which only makes the SNR gate
// slightly stricter.
class NoiseFloor {
 public:
  NoiseFloor(double frame_s, double smoothing_s = 0.01, double window_s = 2.0, int subwindows = 8);
  // Inline: the detector adds every envelope frame of four bands.
  void Add(double power) {
    if (!started_) {
      smoothed_ = power;
      current_min_ = power;
      started_ = true;
    } else {
      smoothed_ += alpha_ * (power - smoothed_);
      current_min_ = std::min(current_min_, smoothed_);
    }
    if (++filled_ == subwindow_frames_) Rotate();
  }
  // Add for each of powers in turn, writing power() after each to floors (as many): the state
  // in locals between the sub-window rotations, not a chain through the members.
  void AddBlock(std::span<const double> powers, double* floors);
  // AddBlock for each of `floors`, floor f taking powers[f] and writing to out[f]. Where the
  // floors are in step (as many powers each, and as many frames added before with the same
  // sub-window, as the detection bands' floors are), they run side by side, every floor's
  // arithmetic exactly as alone: each smoothing step waits on the one before, and one floor at a
  // time left the processor waiting on that chain (3 % of analysing a WAV for three bands).
  static void AddBlocks(std::span<NoiseFloor* const> floors,
                        std::span<const std::span<const double>> powers,
                        std::span<double* const> out);
  // The floor in dB re full scale (power 1); -140 dB for digital silence.
  double db() const;
  // The dB db() gives for a floor of this power (as read from power()).
  static double ToDb(double power);
  // The floor as a power (before the -140 dB clamp of db()); 0 before the first Add.
  double power() const {
    double floor = started_ ? current_min_ : 0.0;
    if (stored_ > 0) floor = std::min(floor, stored_min_);
    return floor;
  }
  // False until the first Add: db() then reads -140 dB, which is no measurement.
  bool started() const { return started_; }

 private:
  void Rotate();  // stores the finished sub-window's minimum
  template <std::size_t N>
  static void AddInStep(std::span<NoiseFloor* const> floors,
                        std::span<const std::span<const double>> powers,
                        std::span<double* const> out);

  double alpha_ = 1;
  long long subwindow_frames_ = 1;
  long long filled_ = 0;
  bool started_ = false;
  double smoothed_ = 0;
  double current_min_ = 0;
  std::vector<double> minima_;
  std::size_t next_ = 0;
  std::size_t stored_ = 0;
  double stored_min_ = 0;  // of the stored minima
  // The last floor db() converted and its dB (NaN: none yet).
  mutable double cached_floor_ = std::numeric_limits<double>::quiet_NaN();
  mutable double cached_db_ = 0;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_NOISE_FLOOR_H_
