#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_SAMPLE_HISTORY_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_SAMPLE_HISTORY_H_

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <span>
#include <vector>

namespace bouncecal::audio {

// The most recent samples of a stream, addressed by their absolute index since the start of
// the stream. A power-of-two ring, so memory stays fixed however long the stream runs.
template <typename T>
class SampleHistory {
 public:
  explicit SampleHistory(std::size_t min_capacity) {
    std::size_t capacity = 1;
    while (capacity < min_capacity) capacity *= 2;
    buffer_.assign(capacity, T{});
    mask_ = capacity - 1;
  }

  void Push(T value) { buffer_[static_cast<std::size_t>(count_++) & mask_] = value; }
  // At most two contiguous copies (before and after the ring wraps), not one masked store per
  // sample: the detector pushes every sample of four streams.
  void PushBlock(std::span<const T> values) {
    if (values.size() > buffer_.size()) {  // only the newest capacity samples stay
      count_ += static_cast<std::int64_t>(values.size() - buffer_.size());
      values = values.last(buffer_.size());
    }
    const std::size_t at = static_cast<std::size_t>(count_) & mask_;
    const std::size_t first = std::min(values.size(), buffer_.size() - at);
    std::copy(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(first),
              buffer_.begin() + static_cast<std::ptrdiff_t>(at));
    std::copy(values.begin() + static_cast<std::ptrdiff_t>(first), values.end(), buffer_.begin());
    count_ += static_cast<std::int64_t>(values.size());
  }
  // Index of the next sample to be pushed (= samples pushed so far).
  std::int64_t end() const { return count_; }
  // Oldest index still held.
  std::int64_t begin() const {
    const auto capacity = static_cast<std::int64_t>(buffer_.size());
    return count_ > capacity ? count_ - capacity : 0;
  }
  std::size_t capacity() const { return buffer_.size(); }
  // The held samples from `index` on, at most `count` of them, as far as they are contiguous in
  // the ring (so fewer when it wraps): readers of a long run take it in at most two views.
  std::span<const T> Contiguous(std::int64_t index, std::size_t count) const {
    assert(index >= begin() && index + static_cast<std::int64_t>(count) <= end());
    const std::size_t at = static_cast<std::size_t>(index) & mask_;
    return {buffer_.data() + at, std::min(count, buffer_.size() - at)};
  }
  T operator[](std::int64_t index) const {
    assert(index >= begin() && index < end());
    return buffer_[static_cast<std::size_t>(index) & mask_];
  }

 private:
  std::vector<T> buffer_;
  std::size_t mask_ = 0;
  std::int64_t count_ = 0;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_SAMPLE_HISTORY_H_
