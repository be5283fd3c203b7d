#ifndef BOUNCECAL_APPS_PLOT_MIN_MAX_DECIMATOR_H_
#define BOUNCECAL_APPS_PLOT_MIN_MAX_DECIMATOR_H_

#include <cstdint>
#include <span>
#include <vector>

namespace bouncecal::apps {

// The lowest and highest sample in each pixel column of a waveform plot, with the column's
// centre time.
struct WaveformColumns {
  std::vector<double> time_s;
  std::vector<double> min;
  std::vector<double> max;
};

// Reduces a signal of any length to min/max per column, streaming, so an hour of audio plots as
// 2 points per pixel column instead of millions, and a single-sample click still shows (a
// stride or mean decimation would hide it). Samples beyond expected_samples land in the last
// column, so a header that undercounts never loses data.
class MinMaxDecimator {
 public:
  MinMaxDecimator(std::int64_t expected_samples, int columns, int sample_rate_hz);
  void Add(std::span<const float> samples);
  // Columns that received samples, in time order.
  WaveformColumns Finish() const;

 private:
  std::int64_t expected_samples_;
  int sample_rate_hz_;
  std::int64_t seen_ = 0;
  std::vector<float> min_;
  std::vector<float> max_;
  std::vector<std::int64_t> first_;
  std::vector<std::int64_t> last_;
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PLOT_MIN_MAX_DECIMATOR_H_
