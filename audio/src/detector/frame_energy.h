#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_FRAME_ENERGY_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_FRAME_ENERGY_H_

#include <cstddef>
#include <cstring>
#include <span>

namespace bouncecal::audio {

// Sum of x^2 in double (each square exact) in four interleaved partial sums: one running sum is
// a chain of dependent additions, four times the latency per sample, and it was the detector's
// largest single cost outside the FFTs. The order of the additions changes the sum by a few
// units in the last place of a double only. The four sums are one vector (GCC's vector
// extension), so a build for AVX keeps them in one register: the same four sums, in half the
// instructions.
inline double SumOfSquares(std::span<const float> x) {
  using Float4 = float __attribute__((vector_size(16)));
  using Double4 = double __attribute__((vector_size(32)));
  Double4 sums = {0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 4 <= x.size(); i += 4) {
    Float4 four;
    std::memcpy(&four, x.data() + i, sizeof four);
    const Double4 wide = __builtin_convertvector(four, Double4);
    sums += wide * wide;
  }
  double s0 = sums[0];
  for (; i < x.size(); ++i) s0 += double{x[i]} * x[i];
  return (s0 + sums[1]) + (sums[2] + sums[3]);
}

// The mean squares of `count` whole frames of `hop` samples from x into out: out[k] is
// SumOfSquares of frame k (the same lanes, the same additions in the same order) divided by hop,
// the same doubles to the bit.
void FrameMeanSquares(const float* x, std::size_t hop, std::size_t count, double* out);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_FRAME_ENERGY_H_
