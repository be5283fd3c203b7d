#ifndef BOUNCECAL_DEM_ENGINE_SIMD_HELPERS_H_
#define BOUNCECAL_DEM_ENGINE_SIMD_HELPERS_H_

// The packing engine's x86 SIMD helpers: whether the wider builds of the contact arithmetic
// exist, the target strings they are compiled with, and the 4x4 transposes of the dense pair
// pass. GCC does not vectorise a gather of whole particle records into per-component arrays, so
// that pass reads four records as rows and transposes them in registers (and back for the
// results). Only the engine's translation units include this (see engine_impl.h).

#include <cstddef>

// The contact arithmetic is also compiled for AVX2 and AVX-512 and picked at run time: the build
// itself targets baseline x86-64 (CI and users' machines may lack either).
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
#define BOUNCECAL_SCENE_HAS_SIMD_PATHS 1
#include <immintrin.h>
#else
#define BOUNCECAL_SCENE_HAS_SIMD_PATHS 0
#endif

// The sanitized build (BOUNCECAL_SANITIZE) leaves the AVX-512 build out: it is the AVX2 build's
// source (the same gathers, stages and scatters) under another target, and at that build's -O0
// the compiler vectorises neither (their only vector code is the same AVX2 intrinsics), so the
// sanitizers find nothing in it that they miss in the AVX2 build; yet under ASan+UBSan each SIMD
// build of every law and physics set costs about what the baseline does to compile
// (engine_3d_part0.cc, 2026-12-04: 66-72 CPU s with both SIMD builds, 44 s with AVX2 alone, 29 s
// with neither). Every kAvx512 request then runs the AVX2 build.
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS && !defined(BOUNCECAL_SCENE_NO_AVX512)
#define BOUNCECAL_SCENE_HAS_AVX512_PATH 1
#else
#define BOUNCECAL_SCENE_HAS_AVX512_PATH 0
#endif

// The attributes of the AVX-512 build, at the full 512-bit width (8 contacts per instruction): at
// 256 bits it gained nothing over AVX2. Clang's target attribute does not take the width (it
// ignores the whole string, and then the AVX2 helpers cannot be inlined); its min_vector_width
// says the same.
#if defined(__clang__)
#define BOUNCECAL_SCENE_AVX512 \
  gnu::target("avx512f,avx512dq,avx512vl"), clang::min_vector_width(512)
#else
#define BOUNCECAL_SCENE_AVX512 gnu::target("avx512f,avx512dq,avx512vl,prefer-vector-width=512")
#endif

namespace bouncecal::dem::scene {

#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
// Four 4-double rows in, four columns out.
[[gnu::always_inline, gnu::target("avx2")]] inline void Transpose4(__m256d& r0, __m256d& r1,
                                                                   __m256d& r2, __m256d& r3) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  r3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}

// The 32-byte-aligned rows at byte `offset` in four records, as columns (x, y, z, scalar).
template <class Record>
[[gnu::always_inline, gnu::target("avx2")]] inline void LoadColumns(
    const Record* const (&record)[4], std::size_t offset, __m256d (&column)[4]) {
  for (int q = 0; q < 4; ++q) {
    column[q] = _mm256_load_pd(
        reinterpret_cast<const double*>(reinterpret_cast<const char*>(record[q]) + offset));
  }
  Transpose4(column[0], column[1], column[2], column[3]);
}

// Four 3-vectors stored one after the other (12 doubles, any alignment) as their x, y and z
// columns: three loads and six shuffles instead of twelve scalar copies.
[[gnu::always_inline, gnu::target("avx2")]] inline void LoadThreeColumns(const double* rows,
                                                                         __m256d& x, __m256d& y,
                                                                         __m256d& z) {
  const __m256d a = _mm256_loadu_pd(rows);               // x0 y0 | z0 x1
  const __m256d b = _mm256_loadu_pd(rows + 4);           // y1 z1 | x2 y2
  const __m256d c = _mm256_loadu_pd(rows + 8);           // z2 x3 | y3 z3
  const __m256d p = _mm256_blend_pd(a, b, 0xC);          // x0 y0 | x2 y2
  const __m256d q = _mm256_permute2f128_pd(a, c, 0x21);  // z0 x1 | z2 x3
  const __m256d r = _mm256_blend_pd(b, c, 0xC);          // y1 z1 | y3 z3
  x = _mm256_shuffle_pd(p, q, 0xA);
  y = _mm256_shuffle_pd(p, r, 0x5);
  z = _mm256_shuffle_pd(q, r, 0xA);
}

// The inverse of LoadThreeColumns: the x, y and z columns of four 3-vectors stored as 12
// consecutive doubles.
[[gnu::always_inline, gnu::target("avx2")]] inline void StoreThreeColumns(__m256d x, __m256d y,
                                                                          __m256d z, double* rows) {
  const __m256d p = _mm256_shuffle_pd(x, y, 0x0);  // x0 y0 | x2 y2
  const __m256d q = _mm256_shuffle_pd(z, x, 0xA);  // z0 x1 | z2 x3
  const __m256d r = _mm256_shuffle_pd(y, z, 0xF);  // y1 z1 | y3 z3
  _mm256_storeu_pd(rows, _mm256_permute2f128_pd(p, q, 0x20));
  _mm256_storeu_pd(rows + 4, _mm256_blend_pd(r, p, 0xC));
  _mm256_storeu_pd(rows + 8, _mm256_permute2f128_pd(q, r, 0x31));
}

// Four contacts' column of a block scratch (16-byte aligned) to and from doubles: the dense pair
// pass gathers and writes back in double, and a single-precision block (ContactScratch<Dim,
// float>) converts at this boundary. For a double block they are the plain load and store.
[[gnu::always_inline, gnu::target("avx2")]] inline void StoreColumn(double* to, __m256d v) {
  _mm256_store_pd(to, v);
}
[[gnu::always_inline, gnu::target("avx2")]] inline void StoreColumn(float* to, __m256d v) {
  _mm_store_ps(to, _mm256_cvtpd_ps(v));
}
[[gnu::always_inline, gnu::target("avx2")]] inline __m256d LoadColumn(const double* from) {
  return _mm256_load_pd(from);
}
[[gnu::always_inline, gnu::target("avx2")]] inline __m256d LoadColumn(const float* from) {
  return _mm256_cvtps_pd(_mm_load_ps(from));
}
#endif

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_SIMD_HELPERS_H_
