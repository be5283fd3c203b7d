#ifndef BOUNCECAL_AUDIO_SRC_DSP_FFT_WISDOM_H_
#define BOUNCECAL_AUDIO_SRC_DSP_FFT_WISDOM_H_

#include <array>

namespace bouncecal::audio {

// Plans for the detector's single-precision transforms, measured once and shipped with the source
// as FFTW wisdom (fftwf_wisdom.inc, written by bench/fft_wisdom_bench --generate).
//
// Why: the FFTs are about two fifths of analysing a recording (perf on analyze_bench's 10-minute
// WAV: 39 % of the samples in libfftw3f), and FFTW_ESTIMATE's heuristic plans for the detector's
// sizes take 1.1-1.9 times as long per sample as measured ones (fft_wisdom_bench: 1.22 at 256
// points, 1.41 at 5120, the sizes of 44.1-48 kHz). Plans measured at run time
// (FFTW_MEASURE) would depend on the timing noise of the moment, so two runs could differ in
// the last bits of every filtered sample and, at a threshold, in a decision; shipped plans are the
// same in every run, as ESTIMATE's are. FFTW uses wisdom for any plan of the same problem
// whatever the planner flags asked for (FFTW manual, "Planner Flags"), so RealFft keeps planning
// with FFTW_ESTIMATE.
//
// FFTW accepts wisdom only from its own version and configuration: the wisdom's signature names
// the set of codelets, which depends on the build (Debian 12's libfftw3f 3.3.10: SSE2 and AVX)
// and on the CPU (the AVX codelets register only where the CPU has AVX). Elsewhere the import
// fails as a whole and every plan is ESTIMATE's, as before.

// The transform sizes the wisdom holds: the ringing residual's windows (the power of two near 5.3
// ms: 64 samples at 8 kHz, 256 at 44.1-48 kHz, 1024 at 192 kHz) and the band filter's
// overlap-save blocks (5 * 2^k, 4-8x its kernel: 5120 up to 75 kHz with the default 300 Hz band
// edge, more at higher rates or lower edges).
inline constexpr std::array<int, 10> kShippedWisdomSizes = {32,   64,   128,   256,   512,
                                                            1024, 5120, 10240, 20480, 40960};

// Adds the shipped plans to FFTW's single-precision wisdom, once per process (later calls return
// the first call's result); true where FFTW accepted them. FFTW's wisdom is process-wide, like
// its planner: call with the planner serialised (real_fft.cc's lock).
bool ImportShippedFftwfWisdom();

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DSP_FFT_WISDOM_H_
