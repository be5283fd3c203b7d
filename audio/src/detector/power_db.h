#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_POWER_DB_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_POWER_DB_H_

#include <bit>
#include <cstdint>

namespace bouncecal::audio {

// 10 log10(power) for a finite power > 0, to within 1e-9 dB, about five times faster than
// std::log10: the detector converts every envelope frame of every band to dB (four bands at
// 4 kHz frame rate), which took 15 % of the analysis time with std::log10. The binary exponent
// comes from the bits; the mantissa m, scaled into [sqrt(1/2), sqrt(2)), goes through
// ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.172, whose series to s^11 leaves a
// relative error below 1e-10 (Abramowitz & Stegun 4.1.28). Pure and deterministic; results do
// not depend on the platform's libm.
inline double PowerToDb(double power) {
  constexpr double kDbPerNeper = 4.3429448190325182765;   // 10 / ln 10
  constexpr double kDbPerOctave = 3.0102999566398119521;  // 10 log10 2
  constexpr double kSqrtHalf = 0.70710678118654752440;
  const auto bits = std::bit_cast<std::uint64_t>(power);
  auto exponent = static_cast<int>((bits >> 52) & 0x7ff) - 1023;
  double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);
  if (exponent == -1023) {  // subnormal: renormalise
    return PowerToDb(power * 0x1p64) - 64 * kDbPerOctave;
  }
  if (m > 2 * kSqrtHalf) {  // m in [1, 2): move the upper part to [sqrt(1/2), 1)
    m *= 0.5;
    ++exponent;
  }
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  const double series =
      s * (1.0 + s2 * (1.0 / 3 + s2 * (1.0 / 5 + s2 * (1.0 / 7 + s2 * (1.0 / 9 + s2 / 11)))));
  return exponent * kDbPerOctave + 2.0 * kDbPerNeper * series;
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_POWER_DB_H_
