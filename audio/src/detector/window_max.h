#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_

#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace bouncecal::audio {

// Maximum of the last `window` values of a stream, in O(1) per value without data-dependent
// branches (van Herk 1992; Gil & Werman 1993): the stream is cut into blocks of `window`
// values; the window ending at value i is the suffix of one block (its suffix maxima are
// computed once, when the block completes) and the prefix of the next (a running maximum).
// A monotonic queue does the same work with a loop whose length depends on the data; on noisy
// envelopes its branches mispredicted on every frame of every band of the detector.
class WindowMax {
 public:
  explicit WindowMax(std::size_t window)
      : window_(std::max<std::size_t>(1, window)),
        values_(window_),
        suffix_(window_, -std::numeric_limits<double>::infinity()) {}

  void Push(double value) {
    prefix_ = position_ == 0 ? value : std::max(prefix_, value);
    values_[position_] = value;
    if (position_ + 1 == window_) {
      max_ = prefix_;
      // The block is complete: its suffix maxima serve the next `window` pushes.
      double suffix = -std::numeric_limits<double>::infinity();
      for (std::size_t i = window_; i-- > 0;) {
        suffix = std::max(suffix, values_[i]);
        suffix_[i] = suffix;
      }
      position_ = 0;
    } else {
      max_ = std::max(suffix_[position_ + 1], prefix_);
      ++position_;
    }
  }
  // Push for each of values in turn, writing max() after each to maxima (as many): the state in
  // locals, so a block of pushes is not a chain of stores and reloads through the members.
  void PushBlock(std::span<const double> values, double* maxima) {
    double prefix = prefix_;
    double max = max_;
    std::size_t position = position_;
    double* block = values_.data();
    double* suffix_maxima = suffix_.data();
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double value = values[i];
      prefix = position == 0 ? value : std::max(prefix, value);
      block[position] = value;
      if (position + 1 == window_) {
        max = prefix;
        double suffix = -std::numeric_limits<double>::infinity();
        for (std::size_t j = window_; j-- > 0;) {
          suffix = std::max(suffix, block[j]);
          suffix_maxima[j] = suffix;
        }
        position = 0;
      } else {
        max = std::max(suffix_maxima[position + 1], prefix);
        ++position;
      }
      maxima[i] = max;
    }
    prefix_ = prefix;
    max_ = max;
    position_ = position;
  }
  // Of the last `window` values pushed (of all of them while fewer were pushed; minus infinity
  // before the first).
  double max() const { return max_; }

 private:
  std::size_t window_;
  std::vector<double> values_;  // of the current block
  std::vector<double> suffix_;  // suffix maxima of the last complete block
  std::size_t position_ = 0;    // in the current block
  double prefix_ = 0;
  double max_ = -std::numeric_limits<double>::infinity();
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_
