#include "detector/window_max.h"

#include <algorithm>

namespace bouncecal::audio {
namespace {

// to[i] = max(from[i], from[i + shift]) for i < count; from and to do not overlap, so the
// compiler needs no run-time check before vectorising.
[[gnu::always_inline]] inline void PairwiseMaxima(const double* __restrict from, std::size_t shift,
                                                  std::size_t count, double* __restrict to) {
  for (std::size_t i = 0; i < count; ++i) to[i] = std::max(from[i], from[i + shift]);
}

}  // namespace

// Also compiled for AVX, picked when the library loads where the processor has it: four maxima
// per instruction instead of two, the same values (a maximum does not round).
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void WindowMaxima(std::span<const double> x, std::span<const WindowRun> runs,
                  std::vector<double>& scratch) {
  const std::size_t n = x.size();
  const double* from = x.data();
  double* to = nullptr;
  double* spare = nullptr;
  // from[i] is the maximum of x[i, i + width), for i < n - width + 1.
  std::size_t width = 1;
  for (const WindowRun& run : runs) {
    const std::size_t count = std::min(run.maxima.size(), n - run.offset - run.window + 1);
    if (run.window <= 1) {
      std::copy_n(x.begin() + static_cast<std::ptrdiff_t>(run.offset), count, run.maxima.begin());
      continue;
    }
    if (to == nullptr) {
      scratch.resize(2 * n);
      to = scratch.data();
      spare = scratch.data() + n;
    }
    while (2 * width < run.window) {
      PairwiseMaxima(from, width, n - 2 * width + 1, to);
      width *= 2;
      from = to;
      std::swap(to, spare);
    }
    // width < window <= 2 width: [i, i + width) and [i + window - width, i + window) cover the
    // window, overlapping where window < 2 width (a maximum may count a value twice).
    PairwiseMaxima(from + run.offset, run.window - width, count, run.maxima.data());
  }
}

void WindowMaxima(std::span<const double> x, std::size_t window, std::span<double> maxima,
                  std::vector<double>& scratch) {
  const WindowRun run{0, window, maxima};
  WindowMaxima(x, std::span<const WindowRun>(&run, 1), scratch);
}

}  // namespace bouncecal::audio
