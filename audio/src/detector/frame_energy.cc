#include "detector/frame_energy.h"

namespace bouncecal::audio {
namespace {

using Float4 = float __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));

// SumOfSquares' four lane sums of the hop samples from x, before the lanes are added together
// (into an argument: a returned 32-byte vector would change the ABI between the clones).
[[gnu::always_inline]] inline void LaneSums(const float* x, std::size_t hop, Double4& sums) {
  sums = Double4{0, 0, 0, 0};
  for (std::size_t i = 0; i + 4 <= hop; i += 4) {
    Float4 four;
    std::memcpy(&four, x + i, sizeof four);
    const Double4 wide = __builtin_convertvector(four, Double4);
    sums += wide * wide;
  }
}

}  // namespace

// Four frames at a time: their lane sums are four independent chains (one frame's three or so
// additions wait on each other), and the lanes are then transposed so that the four frames'
// closing additions (s0 + s1) + (s2 + s3) and their divisions by hop are one vector operation
// each, where every frame's lanes were added across its own register, one frame after the other
// (this function was 4 % of analysing a WAV). Each value goes through the same additions in the
// same order as SumOfSquares. Also compiled for AVX, picked when the library loads where the
// processor has it: a lane sum is then one register (AVX has no fused multiply-add, which would
// round differently; that is FMA, not enabled here).
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void FrameMeanSquares(const float* x, std::size_t hop, std::size_t count, double* out) {
  const auto samples = static_cast<double>(hop);
  const Double4 divisor = {samples, samples, samples, samples};
  const std::size_t whole = hop - hop % 4;  // the samples LaneSums takes
  std::size_t k = 0;
  for (; k + 4 <= count; k += 4) {
    const float* frame = x + k * hop;
    Double4 f0, f1, f2, f3;
    LaneSums(frame, hop, f0);
    LaneSums(frame + hop, hop, f1);
    LaneSums(frame + 2 * hop, hop, f2);
    LaneSums(frame + 3 * hop, hop, f3);
    // lane_l[f] = frame f's lane l.
    const Double4 t0 = __builtin_shufflevector(f0, f1, 0, 4, 2, 6);
    const Double4 t1 = __builtin_shufflevector(f0, f1, 1, 5, 3, 7);
    const Double4 t2 = __builtin_shufflevector(f2, f3, 0, 4, 2, 6);
    const Double4 t3 = __builtin_shufflevector(f2, f3, 1, 5, 3, 7);
    Double4 lane0 = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    const Double4 lane1 = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    const Double4 lane2 = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    const Double4 lane3 = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
    // The samples after the last four of a frame go into its lane 0, as in SumOfSquares.
    for (std::size_t f = 0; f < 4 && whole < hop; ++f) {
      double s0 = lane0[f];
      for (std::size_t i = whole; i < hop; ++i) {
        const double value = frame[f * hop + i];
        s0 += value * value;
      }
      lane0[f] = s0;
    }
    const Double4 mean = ((lane0 + lane1) + (lane2 + lane3)) / divisor;
    std::memcpy(out + k, &mean, sizeof mean);
  }
  for (; k < count; ++k) out[k] = SumOfSquares({x + k * hop, hop}) / samples;
}

}  // namespace bouncecal::audio
