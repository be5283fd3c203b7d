#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_LAG_DOTS_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_LAG_DOTS_H_

#include <cstdint>

namespace bouncecal::audio {

// The dot products of a[0, n) with x[j, j + n) for many lags j at once: the inner loop of a
// cross-correlation over lags, which was 27 % of analysing an AAC copy (response_timing.cc) and
// most of the envelope stage's correlation (envelope_alignment.cc). Each lag's sum runs over t in
// order in float, exactly as one lag at a time would, so results do not depend on how the lags
// are grouped.
inline constexpr std::int64_t kLagLanes = 8;

// kLagLanes lags: dot[j] for j < kLagLanes; x must hold n + kLagLanes - 1 values.
void EightLagDots(const float* a, const float* x, std::int64_t n, float* dot);
// 4 kLagLanes lags: dot[j] for j < 4 kLagLanes; x must hold n + 4 kLagLanes - 1 values.
void ThirtyTwoLagDots(const float* a, const float* x, std::int64_t n, float* dot);
// Every lag j < lags: 32 and 8 at a time, the rest one by one; x must hold n + lags - 1 values.
void LagDotProducts(const float* a, const float* x, std::int64_t n, std::int64_t lags, float* dot);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_LAG_DOTS_H_
