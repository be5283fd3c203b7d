#ifndef BOUNCECAL_AUDIO_SRC_SELECT_KTH_H_
#define BOUNCECAL_AUDIO_SRC_SELECT_KTH_H_

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>

namespace bouncecal::audio {

// The k-th smallest of values (k < values.size(), no NaN), reordering values: the same value
// std::nth_element finds, about three times faster on the ~100 bin powers the ringing
// residual takes a quartile of every 5 ms. std::nth_element branches on every comparison,
// which on noise-like data mispredicts half the time; this quickselect partitions without
// branches (Lomuto's scheme with an unconditional swap and a conditional index step), first
// into < pivot and >= pivot, then the upper part into == pivot and > pivot, so ties (digital
// silence: all bins zero) end in one pass. Ranges of up to 16 are finished by insertion sort.
inline float SelectKth(std::span<float> values, std::size_t k) {
  float* a = values.data();
  std::size_t lo = 0;
  std::size_t hi = values.size();
  // Moves the values of [from, hi) that satisfy goes_first to the front; returns their end.
  const auto partition = [a](std::size_t from, std::size_t to, auto goes_first) {
    std::size_t i = from;
    for (std::size_t x = from; x < to; ++x) {
      const float v = a[x];
      const bool first = goes_first(v);
      a[x] = a[i];
      a[i] = v;
      i += first ? 1 : 0;
    }
    return i;
  };
  while (hi - lo > 16) {
    // Median of three against sorted or reversed input.
    float p0 = a[lo], p1 = a[lo + (hi - lo) / 2], p2 = a[hi - 1];
    if (p0 > p1) std::swap(p0, p1);
    if (p1 > p2) std::swap(p1, p2);
    if (p0 > p1) std::swap(p0, p1);
    const float pivot = p1;
    const std::size_t less_end = partition(lo, hi, [pivot](float v) { return v < pivot; });
    if (k < less_end) {
      hi = less_end;
      continue;
    }
    const std::size_t equal_end = partition(less_end, hi, [pivot](float v) { return v == pivot; });
    if (k < equal_end) return pivot;
    lo = equal_end;
  }
  for (std::size_t i = lo + 1; i < hi; ++i) {
    const float v = a[i];
    std::size_t j = i;
    for (; j > lo && a[j - 1] > v; --j) a[j] = a[j - 1];
    a[j] = v;
  }
  return a[k];
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SELECT_KTH_H_
