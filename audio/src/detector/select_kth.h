#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_

#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace bouncecal::audio {

// The k-th smallest of values (k < values.size(), no NaN): the same value std::nth_element
// finds, in a fraction of its time on the ~100 bin powers the ringing residual takes a quartile
// of every 5 ms. values is left unchanged; scratch is resized to twice its size and reused, so
// repeated calls allocate nothing.
//
// guess (optional, > 0) is a value expected near the answer, such as the previous frame's: one
// pass keeps only the values in [0.6, 1.6) x guess, and when the answer's rank falls among
// them the search goes on in those few (for stationary noise a fifth of the bins) instead of
// all. The result does not depend on the guess, only the time does.
//
// A quickselect whose partitions copy between two buffers instead of swapping in place: every
// value is stored both at the front cursor (values below the pivot) and at the back cursor
// (values above it), and only the matching cursor moves, so a pass has no data-dependent
// branch (std::nth_element's mispredict half the time on noise-like data) and no store that
// the next load must wait for (an in-place swap's). Values equal to the pivot move neither
// cursor: they are only counted, which also ends ties (digital silence: all bins zero) in one
// pass. Ranges of up to 16 are finished by counting each value's rank.
inline float SelectKth(std::span<const float> values, std::size_t k, std::vector<float>& scratch,
                       float guess = 0) {
  const std::size_t n = values.size();
  scratch.resize(2 * n);
  const float* from = values.data();
  float* to = scratch.data();
  float* spare = scratch.data() + n;
  std::size_t lo = 0;
  std::size_t hi = n;
  if (guess > 0 && guess <= std::numeric_limits<float>::max()) {
    const float low = 0.6f * guess;
    const float high = 1.6f * guess;
    std::size_t below = 0;   // values < low
    std::size_t inside = 0;  // values in [low, high), copied to the front of `to`
    for (std::size_t x = 0; x < n; ++x) {
      const float v = from[x];
      to[inside] = v;
      inside += (v >= low) & (v < high) ? 1 : 0;
      below += v < low ? 1 : 0;
    }
    if (k >= below && k < below + inside) {
      k -= below;
      hi = inside;
      from = to;
      std::swap(to, spare);
    }
  }
  while (hi - lo > 16) {
    // Median of three against sorted or reversed input.
    float p0 = from[lo], p1 = from[lo + (hi - lo) / 2], p2 = from[hi - 1];
    if (p0 > p1) std::swap(p0, p1);
    if (p1 > p2) std::swap(p1, p2);
    if (p0 > p1) std::swap(p0, p1);
    const float pivot = p1;
    std::size_t below = lo;  // [lo, below): < pivot
    std::size_t above = hi;  // [above, hi): > pivot
    for (std::size_t x = lo; x < hi; ++x) {
      const float v = from[x];
      to[below] = v;
      to[above - 1] = v;
      below += v < pivot ? 1 : 0;
      above -= v > pivot ? 1 : 0;
    }
    if (k >= below && k < above) return pivot;
    if (k < below) {
      hi = below;
    } else {
      lo = above;
    }
    from = to;
    std::swap(to, spare);
  }
  // The last range by rank: the answer is the value with exactly k - lo others before it in
  // sorted order (the smaller ones, and equal ones earlier in the range). Each rank is a
  // branch-free count over at most 16 values; an insertion sort mispredicted at every stop.
  const std::size_t wanted = k - lo;
  for (std::size_t i = lo; i < hi; ++i) {
    const float v = from[i];
    std::size_t rank = 0;
    for (std::size_t j = lo; j < hi; ++j) {
      rank += (from[j] < v) | ((from[j] == v) & (j < i)) ? 1 : 0;
    }
    if (rank == wanted) return v;
  }
  return from[lo];  // not reached: every rank from 0 to hi - lo - 1 is some value's
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_
