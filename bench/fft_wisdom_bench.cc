// The detector's single-precision FFTs with FFTW_ESTIMATE's plans and with the shipped wisdom
// (audio/src/dsp/fft_wisdom.h): nanoseconds per sample of one forward and one inverse transform
// of every size the wisdom holds, the two alternated in rounds and the fastest round of each
// reported (noise only ever adds time). With --generate it measures new plans (FFTW_PATIENT, on
// buffers allocated and planned as RealFft plans them) and prints the wisdom file to ship:
//
//   build/bench/fft_wisdom_bench
//   build/bench/fft_wisdom_bench --generate > audio/src/dsp/fftwf_wisdom.inc
#include <fftw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "dsp/fft_wisdom.h"

namespace {

// Buffers and plans as BasicRealFft makes them (out of place, FFTW's allocator), so the wisdom
// describes the same problems.
class Transforms {
 public:
  Transforms(int size, unsigned flags) : size_(size) {
    real_ = fftwf_alloc_real(static_cast<size_t>(size));
    spectrum_ = fftwf_alloc_complex(static_cast<size_t>(size / 2 + 1));
    forward_ = fftwf_plan_dft_r2c_1d(size, real_, spectrum_, flags);
    inverse_ = fftwf_plan_dft_c2r_1d(size, spectrum_, real_, flags);
    for (int n = 0; n < size; ++n) real_[n] = static_cast<float>(std::sin(0.37 * n));
  }
  Transforms(const Transforms&) = delete;
  Transforms& operator=(const Transforms&) = delete;
  ~Transforms() {
    fftwf_destroy_plan(forward_);
    fftwf_destroy_plan(inverse_);
    fftwf_free(real_);
    fftwf_free(spectrum_);
  }
  // Nanoseconds per sample of `pairs` forward + inverse transforms.
  double NsPerSample(int pairs) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < pairs; ++i) {
      fftwf_execute(forward_);
      fftwf_execute(inverse_);
      // The inverse returns size times the input; keep the values bounded.
      for (int n = 0; n < 4; ++n) real_[n] *= 1.0f / static_cast<float>(size_);
    }
    const std::chrono::duration<double, std::nano> elapsed =
        std::chrono::steady_clock::now() - start;
    return elapsed.count() / (static_cast<double>(pairs) * size_);
  }

 private:
  int size_;
  float* real_ = nullptr;
  fftwf_complex* spectrum_ = nullptr;
  fftwf_plan forward_ = nullptr;
  fftwf_plan inverse_ = nullptr;
};

int Generate() {
  fftwf_forget_wisdom();
  for (int size : bouncecal::audio::kShippedWisdomSizes) {
    std::fprintf(stderr, "planning %d (FFTW_PATIENT)\n", size);
    const Transforms plans(size, FFTW_PATIENT);
  }
  char* wisdom = fftwf_export_wisdom_to_string();
  if (wisdom == nullptr) return 1;
  std::printf(
      "// FFTW single-precision wisdom for the sizes of kShippedWisdomSizes (fft_wisdom.h),\n"
      "// written by `build/bench/fft_wisdom_bench --generate` with %s. Do not edit.\n"
      "constexpr char kFftwfWisdom[] = R\"(%s)\";\n",
      fftwf_version, wisdom);
  fftwf_free(wisdom);
  return 0;
}

int Compare() {
  constexpr int kRounds = 15;
  constexpr double kSamplesPerRound = 2e6;
  std::printf("%s; shipped wisdom %s\n", fftwf_version,
              bouncecal::audio::ImportShippedFftwfWisdom() ? "accepted" : "REFUSED");
  std::printf("%8s %14s %14s %8s\n", "size", "estimate ns/s", "wisdom ns/s", "ratio");
  for (int size : bouncecal::audio::kShippedWisdomSizes) {
    // ESTIMATE's plan without wisdom: made with the wisdom put aside, then restored.
    char* saved = fftwf_export_wisdom_to_string();
    fftwf_forget_wisdom();
    Transforms estimate(size, FFTW_ESTIMATE);
    fftwf_import_wisdom_from_string(saved);
    fftwf_free(saved);
    Transforms shipped(size, FFTW_ESTIMATE);
    const int pairs = std::max(1, static_cast<int>(kSamplesPerRound / size));
    double best_estimate = std::numeric_limits<double>::infinity();
    double best_shipped = best_estimate;
    for (int round = 0; round < kRounds; ++round) {
      best_estimate = std::min(best_estimate, estimate.NsPerSample(pairs));
      best_shipped = std::min(best_shipped, shipped.NsPerSample(pairs));
    }
    std::printf("%8d %14.3f %14.3f %8.3f\n", size, best_estimate, best_shipped,
                best_shipped / best_estimate);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--generate") == 0) return Generate();
  if (argc != 1) {
    std::fprintf(stderr, "usage: fft_wisdom_bench [--generate]\n");
    return 2;
  }
  return Compare();
}
