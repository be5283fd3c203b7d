#ifndef BOUNCECAL_DEM_ENGINE_ENGINE_PAIR_PASS_H_
#define BOUNCECAL_DEM_ENGINE_ENGINE_PAIR_PASS_H_

// The packing engine's pair pass: every step, each listed pair's force, twist and spring, from
// the particle records into the per-pair result arrays that the particle loop then sums
// (Engine::GatherForce). Members of Engine, defined here so that the pair pass reads as one
// piece; engine_impl.h declares them and includes this file after the class, so the pass is
// compiled (and inlined) in the same translation unit as the rest of the step.
//
// A chunk of the pair list runs one of two ways (Engine::PairForces picks it from the chunk's
// previous step): dense, every listed pair through the contact stages in list order, its rows
// gathered and written back four at a time by transposes (simd_helpers.h); or compacted, only
// the interacting pairs gathered into blocks. A pair's arithmetic is the same either way.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

// The pair pass runs one of two ways, chosen per chunk from its previous step: when most
// listed pairs touch (a settled pack), every listed pair goes through the contact stages in
// list order (PairRangeDense): no compaction and no indirection.
// When few do (a pour's falling phase), only the interacting ones are compacted into blocks
// (PairRangeCompacted), which spares the stages the others. A pair's arithmetic is the same
// either way, so the choice changes no bit. Both return the number of interacting pairs.
template <int Dim, class Law, class Phys>
template <class Real>
inline std::int64_t Engine<Dim, Law, Phys>::PairRangeDense(ContactScratch<Dim, Real>& t,
                                                           std::int64_t begin, std::int64_t end) {
  std::int64_t interacting = 0;
  for (std::int64_t b = begin; b < end; b += kBlock) {
    const int n = static_cast<int>(std::min<std::int64_t>(kBlock, end - b));
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
    switch (simd_) {
      case ContactSimd::kAvx512:
#if BOUNCECAL_SCENE_HAS_AVX512_PATH
        interacting += DenseBlockAvx512(t, b, n);
        break;
#endif
      case ContactSimd::kAvx2:
        interacting += DenseBlockAvx2(t, b, n);
        break;
      case ContactSimd::kBaseline:
        interacting += DenseBlockBaseline(t, b, n);
        break;
    }
#else
    interacting += DenseBlockBaseline(t, b, n);
#endif
  }
  return interacting;
}
// Each returns the number of interacting pairs in the block.
template <int Dim, class Law, class Phys>
template <class Real>
inline std::int64_t Engine<Dim, Law, Phys>::DenseBlockBaseline(ContactScratch<Dim, Real>& t,
                                                               std::int64_t b, int n) {
  DenseGather(t, b, 0, n);
  stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
  return DenseScatter(t, b, 0, n);
}
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::target("avx2")]] inline std::int64_t Engine<Dim, Law, Phys>::DenseBlockAvx2(
    ContactScratch<Dim, Real>& t, std::int64_t b, int n) {
  DenseGather(t, b, GatherTransposed(t, b, n), n);
  stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
  std::int64_t interacting = 0;
  const int written = ScatterTransposed(t, b, n, interacting);
  return interacting + DenseScatter(t, b, written, n);
}
template <int Dim, class Law, class Phys>
template <class Real>
[[BOUNCECAL_SCENE_AVX512]] inline std::int64_t Engine<Dim, Law, Phys>::DenseBlockAvx512(
    ContactScratch<Dim, Real>& t, std::int64_t b, int n) {
  DenseGather(t, b, GatherTransposed(t, b, n), n);
  stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
  std::int64_t interacting = 0;
  const int written = ScatterTransposed(t, b, n, interacting);
  return interacting + DenseScatter(t, b, written, n);
}
#endif

#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
// The first multiple of 4 of a dense block's n contacts (3D; none in 2D); returns how many.
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::always_inline, gnu::target("avx2")]] inline int Engine<Dim, Law, Phys>::GatherTransposed(
    ContactScratch<Dim, Real>& t, std::int64_t b, int n) const {
  int k = 0;
  if constexpr (Dim == 3) {
    const std::int32_t* first = this->pairs_.first.data() + b;
    const std::int32_t* second = this->pairs_.second.data() + b;
    const double cutoff_gap_m = Phys::kVanDerWaals ? this->settings_.vdw_cutoff_gap_m : 0.0;
    for (; k + 4 <= n; k += 4) GatherFourTransposed(t, k, b, first, second, cutoff_gap_m);
  }
  return k;
}

// Dense-block contacts k .. k+3 (3D, AVX2 or wider): the same values as the scalar gather,
// by the same IEEE operations, but each particle record is read as whole 32-byte rows and
// transposed, instead of one scalar load and store per component (the scalar gather was
// load/store bound).
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::always_inline, gnu::target("avx2")]] inline void
Engine<Dim, Law, Phys>::GatherFourTransposed(ContactScratch<Dim, Real>& t, int k, std::int64_t b,
                                             const std::int32_t* first, const std::int32_t* second,
                                             double cutoff_gap_m) const {
  const Record* const records = records_.data();
  const Record* const particle_i[4] = {records + first[k], records + first[k + 1],
                                       records + first[k + 2], records + first[k + 3]};
  const Record* const particle_j[4] = {records + second[k], records + second[k + 1],
                                       records + second[k + 2], records + second[k + 3]};
  __m256d xi[4];
  __m256d xj[4];
  LoadColumns(particle_i, offsetof(Record, position_radius), xi);
  LoadColumns(particle_j, offsetof(Record, position_radius), xj);
  __m256d d[3];
  for (int c = 0; c < 3; ++c) {
    d[c] = _mm256_sub_pd(xi[c], xj[c]);
    StoreColumn(&t.normal[c][k], d[c]);
  }
  // From the first square, as SumOfSquares.
  const __m256d d2 =
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])),
                    _mm256_mul_pd(d[2], d[2]));
  const __m256d cutoff = _mm256_add_pd(_mm256_add_pd(xi[3], xj[3]), _mm256_set1_pd(cutoff_gap_m));
  const __m256d within = _mm256_cmp_pd(d2, _mm256_mul_pd(cutoff, cutoff), _CMP_LT_OQ);
  StoreColumn(&t.within[k], _mm256_and_pd(within, _mm256_set1_pd(1.0)));
  StoreColumn(&t.radius_i[k], xi[3]);
  StoreColumn(&t.radius_j[k], xj[3]);
  if constexpr (ContactScratch<Dim, Real>::kSingle) {
    const __m256d touch = _mm256_add_pd(xi[3], xj[3]);
    StoreColumn(&t.square_gap[k], _mm256_sub_pd(_mm256_mul_pd(touch, touch), d2));
  }
  __m256d vi[4];
  __m256d vj[4];
  LoadColumns(particle_i, offsetof(Record, velocity_mass), vi);
  LoadColumns(particle_j, offsetof(Record, velocity_mass), vj);
  for (int c = 0; c < 3; ++c) StoreColumn(&t.velocity[c][k], _mm256_sub_pd(vi[c], vj[c]));
  StoreColumn(&t.mass_i[k], vi[3]);
  StoreColumn(&t.mass_j[k], vj[3]);
  if constexpr (Phys::kRotation) {
    __m256d wi[4];
    __m256d wj[4];
    LoadColumns(particle_i, offsetof(Record, spin_inertia), wi);
    LoadColumns(particle_j, offsetof(Record, spin_inertia), wj);
    for (int c = 0; c < 3; ++c) {
      StoreColumn(&t.spin[c][k],
                  _mm256_add_pd(_mm256_mul_pd(xi[3], wi[c]), _mm256_mul_pd(xj[3], wj[c])));
    }
  }
  if constexpr (Phys::kTangential) {
    // The four springs are 12 consecutive doubles: three loads, turned into columns.
    static_assert(sizeof(V) == 3 * sizeof(double));
    __m256d x;
    __m256d y;
    __m256d z;
    LoadThreeColumns(reinterpret_cast<const double*>(this->pair_shear_.data() + b + k), x, y, z);
    StoreColumn(&t.shear[0][k], x);
    StoreColumn(&t.shear[1][k], y);
    StoreColumn(&t.shear[2][k], z);
  }
  // Only a law with a normal history looks a dense contact's pair up (the write-back indexes
  // the pairs by position).
  if constexpr (Law::kNeedsHistory) {
    for (int q = 0; q < 4; ++q) t.pair[k + q] = static_cast<std::int32_t>(b + k + q);
  }
}

// The first multiple of 4 of a dense block's n contacts written back (3D; none in 2D), four
// at a time: the masked force and twist columns transposed into each pair's 48-byte record,
// the spring columns into its 24-byte one. Same values and selects as DenseScatter (an AND
// with an all-ones or all-zeros mask is the select `mask ? x : +0.0`). Returns how many were
// written; adds the interacting ones to `interacting`.
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::always_inline, gnu::target("avx2")]] inline int Engine<Dim, Law, Phys>::ScatterTransposed(
    const ContactScratch<Dim, Real>& t, std::int64_t b, int n, std::int64_t& interacting) {
  int k = 0;
  if constexpr (Dim == 3) {
    static_assert(sizeof(PairResult) == 6 * sizeof(double) && sizeof(V) == 3 * sizeof(double));
    auto* results = reinterpret_cast<double*>(this->pair_result_.data() + b);
    auto* shear_out = reinterpret_cast<double*>(this->pair_shear_.data() + b);
    std::uint8_t* live = this->pair_live_.data() + b;
    const __m256d zero = _mm256_setzero_pd();
    for (; k + 4 <= n; k += 4) {
      const __m256d within = _mm256_cmp_pd(LoadColumn(&t.within[k]), zero, _CMP_NEQ_OQ);
      const __m256d touching =
          _mm256_and_pd(within, _mm256_cmp_pd(LoadColumn(&t.overlap[k]), zero, _CMP_GT_OQ));
      __m256d row[4];
      for (int c = 0; c < 3; ++c) row[c] = _mm256_and_pd(within, LoadColumn(&t.force[c][k]));
      __m256d twist[3] = {zero, zero, zero};
      if constexpr (Phys::kRotation) {
        for (int c = 0; c < 3; ++c) {
          twist[c] = _mm256_and_pd(touching, LoadColumn(&t.twist[c][k]));
        }
      }
      row[3] = twist[0];
      Transpose4(row[0], row[1], row[2], row[3]);  // row q: force x y z, twist x of pair q
      const __m256d yz_even = _mm256_unpacklo_pd(twist[1], twist[2]);  // pairs 0 and 2
      const __m256d yz_odd = _mm256_unpackhi_pd(twist[1], twist[2]);   // pairs 1 and 3
      const __m128d yz[4] = {_mm256_castpd256_pd128(yz_even), _mm256_castpd256_pd128(yz_odd),
                             _mm256_extractf128_pd(yz_even, 1), _mm256_extractf128_pd(yz_odd, 1)};
      for (int q = 0; q < 4; ++q) {
        double* record = results + 6 * (k + q);
        _mm256_storeu_pd(record, row[q]);
        _mm_storeu_pd(record + 4, yz[q]);
      }
      if constexpr (Phys::kTangential) {
        StoreThreeColumns(_mm256_and_pd(touching, LoadColumn(&t.shear[0][k])),
                          _mm256_and_pd(touching, LoadColumn(&t.shear[1][k])),
                          _mm256_and_pd(touching, LoadColumn(&t.shear[2][k])), shear_out + 3 * k);
      }
      const int within_bits = _mm256_movemask_pd(within);
      const int touching_bits = _mm256_movemask_pd(touching);
      for (int q = 0; q < 4; ++q) {
        live[k + q] = static_cast<std::uint8_t>((within_bits >> q) & 1);
        interacting += (within_bits >> q) & 1;
        if constexpr (Law::kNeedsHistory) {
          if (((touching_bits >> q) & 1) == 0) {
            this->pair_normal_history_[static_cast<std::size_t>(b + k + q)] = NormalHistory{};
          }
        }
      }
    }
  }
  return k;
}
#endif

// Listed pairs b .. b+n-1, every one through the stages: gathered straight from the particles,
// results and springs written in pair order. Pairs beyond the cutoff come out zero by the same
// selects as a separating contact (and `within` for the van der Waals pull).
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::always_inline]] inline void Engine<Dim, Law, Phys>::DenseGather(ContactScratch<Dim, Real>& t,
                                                                       std::int64_t b, int k,
                                                                       int n) const {
  const Record* x = records_.data();
  const std::int32_t* first = this->pairs_.first.data() + b;
  const std::int32_t* second = this->pairs_.second.data() + b;
  const V* shear = this->pair_shear_.data() + b;
  const double cutoff_gap_m = Phys::kVanDerWaals ? this->settings_.vdw_cutoff_gap_m : 0.0;
  for (; k < n; ++k) {
    const std::int32_t i = first[k];
    const std::int32_t j = second[k];
    const Record& particle_i = x[i];
    const Record& particle_j = x[j];
    const double r_i = particle_i.position_radius.s;
    const double r_j = particle_j.position_radius.s;
    double d[Dim];
    for (int c = 0; c < Dim; ++c) {
      d[c] = particle_i.position_radius.v[c] - particle_j.position_radius.v[c];
      t.normal[c][k] = static_cast<Real>(d[c]);
    }
    const double d2 = SumOfSquares<Dim>(d);
    const double cutoff_m = r_i + r_j + cutoff_gap_m;
    t.within[k] = d2 < cutoff_m * cutoff_m ? Real{1} : Real{0};
    t.radius_i[k] = static_cast<Real>(r_i);
    t.radius_j[k] = static_cast<Real>(r_j);
    if constexpr (ContactScratch<Dim, Real>::kSingle) {
      const double touch = r_i + r_j;
      t.square_gap[k] = static_cast<Real>(touch * touch - d2);
    }
    t.mass_i[k] = static_cast<Real>(particle_i.velocity_mass.s);
    t.mass_j[k] = static_cast<Real>(particle_j.velocity_mass.s);
    for (int c = 0; c < Dim; ++c) {
      t.velocity[c][k] =
          static_cast<Real>(particle_i.velocity_mass.v[c] - particle_j.velocity_mass.v[c]);
    }
    if constexpr (Phys::kRotation) {
      if constexpr (Dim == 3) {
        for (int c = 0; c < 3; ++c) {
          t.spin[c][k] = static_cast<Real>(r_i * particle_i.spin_inertia.w[c] +
                                           r_j * particle_j.spin_inertia.w[c]);
        }
      } else {
        t.spin[0][k] =
            static_cast<Real>(r_i * particle_i.spin_inertia.w + r_j * particle_j.spin_inertia.w);
      }
    }
    if constexpr (Phys::kTangential) {
      for (int c = 0; c < Dim; ++c) t.shear[c][k] = static_cast<Real>(shear[k][c]);
    }
    if constexpr (Law::kNeedsHistory) t.pair[k] = static_cast<std::int32_t>(b + k);
  }
}

// Writes the results, springs and live flags of dense-block contacts k .. n-1; returns how
// many interact.
template <int Dim, class Law, class Phys>
template <class Real>
[[gnu::always_inline]] inline std::int64_t Engine<Dim, Law, Phys>::DenseScatter(
    const ContactScratch<Dim, Real>& t, std::int64_t b, int k, int n) {
  auto* results = this->pair_result_.data() + b;
  V* shear_out = this->pair_shear_.data() + b;
  std::uint8_t* live = this->pair_live_.data() + b;
  std::int64_t interacting = 0;
  for (; k < n; ++k) {
    // A pair beyond the cutoff is zeroed whole, as the compacted pass clears it, even in
    // the last-ulp case where its overlap reads positive.
    const bool within = t.within[k] != 0;
    const bool touching = within & (t.overlap[k] > 0);
    for (int c = 0; c < Dim; ++c) {
      results[k].force_n[c] = within ? static_cast<double>(t.force[c][k]) : 0.0;
    }
    if constexpr (Phys::kRotation) {
      if constexpr (Dim == 3) {
        for (int c = 0; c < 3; ++c) {
          results[k].twist_n[c] = touching ? static_cast<double>(t.twist[c][k]) : 0.0;
        }
      } else {
        results[k].twist_n = touching ? static_cast<double>(t.twist[0][k]) : 0.0;
      }
    }
    if constexpr (Phys::kTangential) {
      for (int c = 0; c < Dim; ++c) {
        shear_out[k][c] = touching ? static_cast<double>(t.shear[c][k]) : 0.0;
      }
    }
    if constexpr (Law::kNeedsHistory) {
      if (!touching) {
        this->pair_normal_history_[static_cast<std::size_t>(b + k)] = NormalHistory{};
      }
    }
    live[k] = within ? 1 : 0;
    interacting += within ? 1 : 0;
  }
  return interacting;
}

// Every listed pair's distance is measured and its separation vector and radii are written
// into the next free slot of the block scratch, but the slot is only kept (the count advances)
// when the pair interacts: no data-dependent branch, and the positions are read once, not
// again by the block gather. Once kBlock interacting pairs have gathered, they go through the
// contact laws together (ContactBlock).
template <int Dim, class Law, class Phys>
inline std::int64_t Engine<Dim, Law, Phys>::PairRangeCompacted(Scratch& t, std::int64_t begin,
                                                               std::int64_t end) {
  std::int64_t interacting = 0;
  const Record* x = records_.data();
  const std::int32_t* first = this->pairs_.first.data();
  const std::int32_t* second = this->pairs_.second.data();
  std::uint8_t* live = this->pair_live_.data();
  // Pair terms are recomputed from the particles rather than stored per pair, to keep
  // the per-pair arrays (read every step) small.
  const double cutoff_gap_m = Phys::kVanDerWaals ? this->settings_.vdw_cutoff_gap_m : 0.0;
  auto* results = this->pair_result_.data();
  int count = 0;
  for (std::int64_t p = begin; p < end; ++p) {
    const std::int32_t i = first[p];
    const std::int32_t j = second[p];
    const V d = x[i].position_radius.v - x[j].position_radius.v;
    const double cutoff_m = x[i].position_radius.s + x[j].position_radius.s + cutoff_gap_m;
    const bool interacts = d.squaredNorm() < cutoff_m * cutoff_m;
    t.pair[count] = static_cast<std::int32_t>(p);
    t.first[count] = i;
    t.second[count] = j;
    for (int c = 0; c < Dim; ++c) t.normal[c][count] = d[c];
    t.radius_i[count] = x[i].position_radius.s;
    t.radius_j[count] = x[j].position_radius.s;
    count += interacts ? 1 : 0;
    interacting += interacts ? 1 : 0;
    // An interacting pair's result and spring are written by its contact block. A pair
    // that does not interact has them zero, and they are almost always zero already:
    // only a pair that has just separated is cleared (a predictable branch), so the
    // others' records are neither written nor read. `&`, not `&&`: whether a listed
    // pair interacts is random, so a short-circuit jump on it would be mispredicted.
    if (!interacts & (live[p] != 0)) {
      const auto q = static_cast<std::size_t>(p);
      results[q] = {V::Zero(), ZeroSpin<Dim>()};
      if constexpr (Phys::kTangential) this->pair_shear_[q] = V::Zero();
      if constexpr (Law::kNeedsHistory) this->pair_normal_history_[q] = {};
    }
    live[p] = interacts ? 1 : 0;
    if (count == kBlock) {  // taken once per kBlock contacts: predictable
      ContactBlock(kBlock, t);
      count = 0;
    }
  }
  if (count > 0) ContactBlock(count, t);
  return interacting;
}

// The forces of the first `n` pairs of the block (all closer than their cutoff; the distance
// pass has filled in pair, normal = x_i - x_j and the radii); their whole pair_result_ is
// written. The rest of the block is gathered from the particles, then the stages run over it
// (contact_stages.h).
template <int Dim, class Law, class Phys>
inline void Engine<Dim, Law, Phys>::ContactBlock(int n, Scratch& t) {
  GatherBlock(n, t);
  if (t.single == nullptr) {
    stages_.template Run<false>(simd_, t, n, this->pair_normal_history_);
  } else {
    stages_.RunSingle(simd_, t, n, this->pair_normal_history_);
  }
  ScatterBlock(n, t);
}

template <int Dim, class Law, class Phys>
inline void Engine<Dim, Law, Phys>::GatherBlock(int n, Scratch& t) const {
  for (int k = 0; k < n; ++k) {
    const std::int32_t p = t.pair[k];
    const auto i = static_cast<std::size_t>(t.first[k]);
    const auto j = static_cast<std::size_t>(t.second[k]);
    const PackedVector<Dim>& v_i = records_[i].velocity_mass;
    const PackedVector<Dim>& v_j = records_[j].velocity_mass;
    const double r_i = t.radius_i[k];
    const double r_j = t.radius_j[k];
    t.mass_i[k] = v_i.s;
    t.mass_j[k] = v_j.s;
    for (int c = 0; c < Dim; ++c) t.velocity[c][k] = v_i.v[c] - v_j.v[c];
    if constexpr (Phys::kRotation) {
      if constexpr (Dim == 3) {
        for (int c = 0; c < 3; ++c)
          t.spin[c][k] = r_i * records_[i].spin_inertia.w[c] + r_j * records_[j].spin_inertia.w[c];
      } else {
        t.spin[0][k] = r_i * records_[i].spin_inertia.w + r_j * records_[j].spin_inertia.w;
      }
    }
    if constexpr (Phys::kTangential) {
      const V& shear = this->pair_shear_[static_cast<std::size_t>(p)];
      for (int c = 0; c < Dim; ++c) t.shear[c][k] = shear[c];
    }
  }
}

template <int Dim, class Law, class Phys>
inline void Engine<Dim, Law, Phys>::ScatterBlock(int n, const Scratch& t) {
  for (int k = 0; k < n; ++k) {
    const auto p = static_cast<std::size_t>(t.pair[k]);
    auto& result = this->pair_result_[p];
    for (int c = 0; c < Dim; ++c) result.force_n[c] = t.force[c][k];
    const bool touching = t.overlap[k] > 0;
    if constexpr (Phys::kRotation) {
      if constexpr (Dim == 3) {
        for (int c = 0; c < 3; ++c) result.twist_n[c] = touching ? t.twist[c][k] : 0.0;
      } else {
        result.twist_n = touching ? t.twist[0][k] : 0.0;
      }
    }
    if constexpr (Phys::kTangential) {
      auto& shear = this->pair_shear_[p];
      for (int c = 0; c < Dim; ++c) shear[c] = touching ? t.shear[c][k] : 0.0;
    }
    if constexpr (Law::kNeedsHistory) {
      if (!touching) this->pair_normal_history_[p] = NormalHistory{};
    }
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_ENGINE_PAIR_PASS_H_
