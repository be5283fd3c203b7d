#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace bouncecal::audio {

namespace select_kth_detail {

// The k-th smallest of from[lo, hi) (k in [lo, hi)): a quickselect whose partitions copy between
// two buffers instead of swapping in place. Every value is stored both at the front cursor
// (values below the pivot) and at the back cursor (values above it), and only the matching
// cursor moves, so a pass has no data-dependent branch (std::nth_element's mispredict half the
// time on noise-like data) and no store that the next load must wait for (an in-place swap's).
// Values equal to the pivot move neither cursor: they are only counted, which also ends ties
// (digital silence: all bins zero) in one pass. Ranges of up to 16 are finished by counting
// each value's rank. `to` and `spare` hold hi values each; `spare` may be `from` itself, which
// the first pass reads for the last time.
inline float Quickselect(const float* from, float* to, float* spare, std::size_t lo, std::size_t hi,
                         std::size_t k) {
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
  // The last range by rank: the answer is the value with at most k - lo others below it and
  // more than k - lo at or below it. Each is a branch-free count over at most 16 values (it
  // vectorises); an insertion sort mispredicted at every stop.
  const std::size_t wanted = k - lo;
  for (std::size_t i = lo; i < hi; ++i) {
    const float v = from[i];
    std::uint32_t less = 0, equal = 0;
    for (std::size_t j = lo; j < hi; ++j) {
      less += from[j] < v ? 1 : 0;
      equal += from[j] == v ? 1 : 0;
    }
    if (less <= wanted && wanted < less + equal) return v;
  }
  return from[lo];  // not reached: every rank from 0 to hi - lo - 1 is some value's
}

}  // namespace select_kth_detail

// The k-th smallest of values (k < values.size(), no NaN): the same value std::nth_element
// finds, in a fraction of its time on the ~100 bin powers the ringing residual takes a quartile
// of every 5 ms. values is left unchanged; scratch is resized to twice its size and reused, so
// repeated calls allocate nothing.
//
// guess (optional, > 0) is a value expected near the answer, such as the previous frame's. One
// counting pass (no data-dependent branch; it vectorises) ranks the answer among the bracket
// edges kGuessSteps x guess; the values between the two edges around it (for stationary noise
// a tenth of the bins) are then gathered and the search goes on in those few instead of all.
// Where the guess is far off, the bracket is the values below the lowest edge or from the
// highest on. The result does not depend on the guess, only the time does: the values in
// [edge a, edge b) are exactly those of ranks (values below edge a) to (values below edge b) - 1.
inline float SelectKth(std::span<const float> values, std::size_t k, std::vector<float>& scratch,
                       float guess = 0) {
  const std::size_t n = values.size();
  scratch.resize(2 * n);
  const float* from = values.data();
  if (!(guess > 0 && guess <= std::numeric_limits<float>::max())) {
    return select_kth_detail::Quickselect(from, scratch.data(), scratch.data() + n, 0, n, k);
  }
  // A quartile of 126 noise bins moves by ~20 % from one window to the next: four edges keep the
  // bracket small where the guess is close, and the outer ones still catch most of the rest.
  // Six or eight edges made the counting pass cost what they saved in the gathering.
  constexpr std::array<float, 4> kGuessSteps = {0.6f, 0.85f, 1.15f, 1.6f};
  constexpr std::size_t kEdges = kGuessSteps.size();
  std::array<float, kEdges> edge;
  // Non-decreasing (rounding is monotonic), so the counts below are too.
  for (std::size_t e = 0; e < kEdges; ++e) edge[e] = kGuessSteps[e] * guess;
  // 32-bit counts (bin powers number far fewer than 2^32): four to a vector register, where
  // 64-bit ones took two.
  std::array<std::uint32_t, kEdges> below{};  // values < edge[e]
  for (std::size_t x = 0; x < n; ++x) {
    const float v = from[x];
    for (std::size_t e = 0; e < kEdges; ++e) below[e] += v < edge[e] ? 1 : 0;
  }
  // The answer lies in [edge[e - 1], edge[e]): minus infinity for e = 0, no upper edge (there may
  // be infinite values) for e = kEdges.
  std::size_t e = 0;
  while (e < kEdges && below[e] <= k) ++e;
  const float low = e == 0 ? -std::numeric_limits<float>::infinity() : edge[e - 1];
  const std::size_t skipped = e == 0 ? 0 : below[e - 1];
  const bool bounded = e < kEdges;
  const float high = bounded ? edge[e] : 0.0f;
  float* const gathered = scratch.data();
  std::size_t m = 0;
  std::size_t x = 0;
#if defined(__SSE2__)
  // Four comparisons at a time into a bit mask per 64 values, whose set bits are then taken in
  // order: a loop over the few values in the bracket instead of a store and a dependent cursor
  // update for every value (the scalar loop below was half this function's time).
  const __m128 low4 = _mm_set1_ps(low);
  const __m128 high4 = _mm_set1_ps(high);
  while (x + 4 <= n) {
    std::uint64_t inside = 0;
    const std::size_t base = x;
    for (; x + 4 <= n && x - base < 64; x += 4) {
      const __m128 four = _mm_loadu_ps(from + x);
      __m128 in = _mm_cmpge_ps(four, low4);
      if (bounded) in = _mm_and_ps(in, _mm_cmplt_ps(four, high4));
      inside |= static_cast<std::uint64_t>(_mm_movemask_ps(in)) << (x - base);
    }
    for (; inside != 0; inside &= inside - 1) {
      gathered[m++] = from[base + static_cast<std::size_t>(std::countr_zero(inside))];
    }
  }
#endif
  for (; x < n; ++x) {
    const float v = from[x];
    gathered[m] = v;
    m += (v >= low) & (!bounded || v < high) ? 1 : 0;
  }
  // The first pass reads `gathered` for the last time, so it is the second buffer's spare.
  return select_kth_detail::Quickselect(gathered, scratch.data() + n, gathered, 0, m, k - skipped);
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_SELECT_KTH_H_
