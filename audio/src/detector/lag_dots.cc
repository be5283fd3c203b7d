#include "detector/lag_dots.h"

#include <cstring>

namespace bouncecal::audio {
namespace {

// kLagLanes x Vectors lags j, each summed over t in order: lane j adds the float product
// a[t] x[t + j] to its float sum exactly as one lag at a time would, so the correlations are bit
// for bit the same; the lanes are vectors (GCC's
// vector extension), since the sum over t cannot be vectorised without reordering it. Four
// vectors at once where the lags allow, because one vector's sum waits on its previous add
// every step and four keep four adds in flight. Also compiled for AVX (no fused multiply-add
// there, which would round differently), picked when the library loads where the processor
// has it.
template <int Vectors>
[[gnu::always_inline]] inline void LagDots(const float* a, const float* x, std::int64_t n,
                                           float* dot) {
  using Float8 = float __attribute__((vector_size(kLagLanes * sizeof(float))));
  Float8 sums[Vectors] = {};
  for (std::int64_t t = 0; t < n; ++t) {
    for (int v = 0; v < Vectors; ++v) {
      Float8 window;
      std::memcpy(&window, x + t + v * kLagLanes, sizeof window);
      sums[v] += a[t] * window;
    }
  }
  std::memcpy(dot, sums, sizeof sums);
}

}  // namespace

// The multiversioned entry points (Clang cannot multiversion a template).
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void EightLagDots(const float* a, const float* x, std::int64_t n, float* dot) {
  LagDots<1>(a, x, n, dot);
}

#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void ThirtyTwoLagDots(const float* a, const float* x, std::int64_t n, float* dot) {
  LagDots<4>(a, x, n, dot);
}

void LagDotProducts(const float* a, const float* x, std::int64_t n, std::int64_t lags, float* dot) {
  std::int64_t k = 0;
  for (; k + 4 * kLagLanes <= lags; k += 4 * kLagLanes) ThirtyTwoLagDots(a, x + k, n, dot + k);
  for (; k + kLagLanes <= lags; k += kLagLanes) EightLagDots(a, x + k, n, dot + k);
  for (; k < lags; ++k) {
    float sum = 0;
    for (std::int64_t t = 0; t < n; ++t) sum += a[t] * x[k + t];
    dot[k] = sum;
  }
}

}  // namespace bouncecal::audio
