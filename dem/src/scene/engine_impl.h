#ifndef BOUNCECAL_DEM_SCENE_ENGINE_IMPL_H_
#define BOUNCECAL_DEM_SCENE_ENGINE_IMPL_H_

// The force loop and integrator, templated on dimension, normal contact law and physics. Only
// the engine factories include this file.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <variant>

#include "scene/contact_stages.h"
#include "scene/engine.h"
#include "scene/integrator.h"
#include "scene/local_damping.h"
#include "scene/particle_records.h"
#include "scene/simd_helpers.h"

namespace bouncecal::dem::scene {

template <int Dim, class Law, class Phys>
class Engine final : public EngineBase<Dim> {
  static_assert(!Phys::kRotation || Phys::kTangential,
                "only the tangential force makes torque (paper 000 eq. 2)");

 public:
  Engine(const EngineSettings& settings, std::vector<Wall<Dim>> walls, Law law)
      : EngineBase<Dim>(settings, std::move(walls)),
        stages_(std::move(law), settings),
        gravity_(this->Gravity()),
        simd_(std::min(settings.max_contact_simd, CpuContactSimd())),
        scratch_(static_cast<std::size_t>(this->pool_->chunks())) {}

  void ComputeForces() override {
    this->EnterWorkingOrder();
    ForcesInWorkingOrder();
    this->LeaveWorkingOrder();
  }

  void Advance(std::int64_t steps) override {
    if (steps <= 0) return;
    this->EnterWorkingOrder();
    if (!this->forces_valid_) {
      ForcesInWorkingOrder();
    } else {
      LoadRecords();
    }
    const std::int32_t n = this->state_.size();
    const double dt = this->settings_.time_step_s;
    const double half_dt = 0.5 * dt;
    auto& pool = *this->pool_;
    std::vector<double> chunk_move2(static_cast<std::size_t>(pool.chunks()), 0.0);
    // Velocity Verlet with the closing half kick of one step fused into the opening half kick
    // and drift of the next, so a step costs two passes (integrator.h).
    auto kick_drift = [&](int chunk, std::int64_t begin, std::int64_t end) {
      double move2 = 0;
      for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
        Load load{this->state_.force_n[i], ZeroSpin<Dim>()};
        if constexpr (Phys::kRotation) load.torque = this->state_.torque_nm[i];
        move2 =
            std::max(move2, VerletKickDrift<Dim, Phys::kRotation>(records_[i], half_dt, dt, load));
      }
      chunk_move2[static_cast<std::size_t>(chunk)] = move2;
    };
    pool.ParallelFor(n, kick_drift);
    for (std::int64_t step = 0; step < steps; ++step) {
      double max_move2 = 0;  // max is exact, so the order of the chunks does not matter
      for (double m : chunk_move2) max_move2 = std::max(max_move2, m);
      if (!this->settings_.brute_force_pairs && 4 * max_move2 > Square(this->skin_m_)) {
        this->pairs_valid_ = false;
      }
      if (!this->pairs_valid_ || this->settings_.stop_at_first_contact) {
        // The rebuild and the first-contact stop work on state_: hand it the current state.
        StoreRecords();
        PrepareStep();
        if (this->settings_.stop_at_first_contact) this->StopFirstContacts();
        LoadRecords();
      }
      PairForces();
      const bool last = step + 1 == steps;
      std::fill(chunk_move2.begin(), chunk_move2.end(), 0.0);
      pool.ParallelFor(n, [&](int chunk, std::int64_t begin, std::int64_t end) {
        double move2 = 0;
        for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
          // The load is handed over in registers: reading back what GatherForce just stored
          // stalled on store forwarding.
          const Load load = GatherForce(i);
          if (last) {
            // Only the last step's load is read again (by the next Advance's opening kick).
            StoreLoad(i, load);
            VerletHalfKick<Dim, Phys::kRotation>(records_[i], half_dt, load);
          } else {
            move2 =
                std::max(move2, VerletKickDrift<Dim, Phys::kRotation>(records_[i], dt, dt, load));
          }
        }
        chunk_move2[static_cast<std::size_t>(chunk)] = move2;
      });
      ++this->steps_;
    }
    StoreRecords();
    this->forces_valid_ = true;
    this->LeaveWorkingOrder();
  }

 private:
  using V = Vec<Dim>;
  using S = Spin<Dim>;
  using PairResult = typename EngineBase<Dim>::PairResult;
  using Record = ParticleRecord<Dim>;
  using Load = ParticleLoad<Dim>;
  using Scratch = ContactScratch<Dim>;
  static constexpr int kBlock = Scratch::kBlock;
  static double Square(double x) { return x * x; }

  void ForcesInWorkingOrder() {
    PrepareStep();
    LoadRecords();
    PairForces();
    const std::int32_t n = this->state_.size();
    for (std::int32_t i = 0; i < n; ++i) StoreLoad(i, GatherForce(i));
    this->forces_valid_ = true;
  }

  // state_ holds the particles outside the stepping loop (and for the rebuild and the
  // first-contact stop); inside it the loop works on records_ (particle_records.h).
  void LoadRecords() { LoadParticleRecords(this->state_, this->position_at_rebuild_, records_); }
  void StoreRecords() { StoreParticleRecords(records_, this->state_); }

  void PrepareStep() {
    if (!this->pairs_valid_) {
      this->RebuildPairs(Phys::kVanDerWaals);
    }
  }

  void StoreLoad(std::int32_t i, const Load& load) {
    this->state_.force_n[i] = load.force;
    if constexpr (Phys::kRotation) this->state_.torque_nm[i] = load.torque;
  }

  // Each chunk of the pair list runs its pairs through the contact stages in blocks of kBlock
  // (vectorised across contacts), either all of them or only the interacting ones (see
  // PairRangeDense). The arithmetic of each pair does not depend on the chunking, the blocking
  // or the choice: results are the same for every thread count.
  //
  // The same chunk then measures its share of the particles against the walls they may touch
  // and sends the touching ones through the same stages (WallBlock). Pairs and particles are
  // split in proportion, so a chunk's range is a compact region for both.
  void PairForces() {
    const auto pair_count = static_cast<std::int64_t>(this->pairs_.size());
    const std::int64_t particle_count = this->walls_.empty() ? 0 : this->state_.size();
    wall_result_.resize(static_cast<std::size_t>(particle_count) * this->walls_.size());
    const std::int64_t items = pair_count + particle_count;
    this->pool_->ParallelFor(items, [this, pair_count, particle_count, items](
                                        int chunk, std::int64_t begin, std::int64_t end) {
      auto& t = scratch_[static_cast<std::size_t>(chunk)];
      const std::int64_t pair_begin = begin * pair_count / items;
      const std::int64_t pair_end = end * pair_count / items;
      const std::int64_t interacting = t.dense ? PairRangeDense(t, pair_begin, pair_end)
                                               : PairRangeCompacted(t, pair_begin, pair_end);
      // Next step's choice for this chunk (its range hardly moves between steps).
      t.dense = static_cast<double>(interacting) >=
                this->settings_.dense_pair_fraction * static_cast<double>(pair_end - pair_begin);
      WallRange(t, begin * particle_count / items, end * particle_count / items);
    });
  }

  // The pair pass runs one of two ways, chosen per chunk from its previous step: when most
  // listed pairs touch (a settled pack), every listed pair goes through the contact stages in
  // list order (PairRangeDense): no compaction and no indirection.
  // When few do (a pour's falling phase), only the interacting ones are compacted into blocks
  // (PairRangeCompacted), which spares the stages the others. A pair's arithmetic is the same
  // either way, so the choice changes no bit. Both return the number of interacting pairs.
  std::int64_t PairRangeDense(Scratch& t, std::int64_t begin, std::int64_t end) {
    std::int64_t interacting = 0;
    for (std::int64_t b = begin; b < end; b += kBlock) {
      const int n = static_cast<int>(std::min<std::int64_t>(kBlock, end - b));
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
      switch (simd_) {
        case ContactSimd::kAvx512:
          interacting += DenseBlockAvx512(t, b, n);
          break;
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
  std::int64_t DenseBlockBaseline(Scratch& t, std::int64_t b, int n) {
    DenseGather(t, b, 0, n);
    stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
    return DenseScatter(t, b, 0, n);
  }
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
  [[gnu::target("avx2")]] std::int64_t DenseBlockAvx2(Scratch& t, std::int64_t b, int n) {
    DenseGather(t, b, GatherTransposed(t, b, n), n);
    stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
    std::int64_t interacting = 0;
    const int written = ScatterTransposed(t, b, n, interacting);
    return interacting + DenseScatter(t, b, written, n);
  }
  [[gnu::target(BOUNCECAL_SCENE_AVX512_TARGET)]] std::int64_t DenseBlockAvx512(Scratch& t,
                                                                               std::int64_t b,
                                                                               int n) {
    DenseGather(t, b, GatherTransposed(t, b, n), n);
    stages_.template Arithmetic<false>(t, n, this->pair_normal_history_);
    std::int64_t interacting = 0;
    const int written = ScatterTransposed(t, b, n, interacting);
    return interacting + DenseScatter(t, b, written, n);
  }
#endif

#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
  // The first multiple of 4 of a dense block's n contacts (3D; none in 2D); returns how many.
  [[gnu::always_inline, gnu::target("avx2")]] inline int GatherTransposed(Scratch& t,
                                                                          std::int64_t b,
                                                                          int n) const {
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
  [[gnu::always_inline, gnu::target("avx2")]] inline void GatherFourTransposed(
      Scratch& t, int k, std::int64_t b, const std::int32_t* first, const std::int32_t* second,
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
    __m256d d2 = _mm256_setzero_pd();
    for (int c = 0; c < 3; ++c) {
      const __m256d d = _mm256_sub_pd(xi[c], xj[c]);
      _mm256_store_pd(&t.normal[c][k], d);
      d2 = _mm256_add_pd(d2, _mm256_mul_pd(d, d));
    }
    const __m256d cutoff = _mm256_add_pd(_mm256_add_pd(xi[3], xj[3]), _mm256_set1_pd(cutoff_gap_m));
    const __m256d within = _mm256_cmp_pd(d2, _mm256_mul_pd(cutoff, cutoff), _CMP_LT_OQ);
    _mm256_store_pd(&t.within[k], _mm256_and_pd(within, _mm256_set1_pd(1.0)));
    _mm256_store_pd(&t.radius_i[k], xi[3]);
    _mm256_store_pd(&t.radius_j[k], xj[3]);
    __m256d vi[4];
    __m256d vj[4];
    LoadColumns(particle_i, offsetof(Record, velocity_mass), vi);
    LoadColumns(particle_j, offsetof(Record, velocity_mass), vj);
    for (int c = 0; c < 3; ++c) _mm256_store_pd(&t.velocity[c][k], _mm256_sub_pd(vi[c], vj[c]));
    _mm256_store_pd(&t.mass_i[k], vi[3]);
    _mm256_store_pd(&t.mass_j[k], vj[3]);
    if constexpr (Phys::kRotation) {
      __m256d wi[4];
      __m256d wj[4];
      LoadColumns(particle_i, offsetof(Record, spin_inertia), wi);
      LoadColumns(particle_j, offsetof(Record, spin_inertia), wj);
      for (int c = 0; c < 3; ++c) {
        _mm256_store_pd(&t.spin[c][k],
                        _mm256_add_pd(_mm256_mul_pd(xi[3], wi[c]), _mm256_mul_pd(xj[3], wj[c])));
      }
    }
    if constexpr (Phys::kTangential) {
      const V* shear = this->pair_shear_.data() + b + k;
      for (int q = 0; q < 4; ++q) {
        for (int c = 0; c < 3; ++c) t.shear[c][k + q] = shear[q][c];
      }
    }
    for (int q = 0; q < 4; ++q) t.pair[k + q] = static_cast<std::int32_t>(b + k + q);
  }

  // The first multiple of 4 of a dense block's n contacts written back (3D; none in 2D), four
  // at a time: the masked force and twist columns transposed into each pair's 48-byte record,
  // the spring columns into its 24-byte one. Same values and selects as DenseScatter (an AND
  // with an all-ones or all-zeros mask is the select `mask ? x : +0.0`). Returns how many were
  // written; adds the interacting ones to `interacting`.
  [[gnu::always_inline, gnu::target("avx2")]] inline int ScatterTransposed(
      const Scratch& t, std::int64_t b, int n, std::int64_t& interacting) {
    int k = 0;
    if constexpr (Dim == 3) {
      static_assert(sizeof(PairResult) == 6 * sizeof(double) && sizeof(V) == 3 * sizeof(double));
      auto* results = reinterpret_cast<double*>(this->pair_result_.data() + b);
      auto* shear_out = reinterpret_cast<double*>(this->pair_shear_.data() + b);
      std::uint8_t* live = this->pair_live_.data() + b;
      const __m256d zero = _mm256_setzero_pd();
      for (; k + 4 <= n; k += 4) {
        const __m256d within = _mm256_cmp_pd(_mm256_load_pd(&t.within[k]), zero, _CMP_NEQ_OQ);
        const __m256d touching =
            _mm256_and_pd(within, _mm256_cmp_pd(_mm256_load_pd(&t.overlap[k]), zero, _CMP_GT_OQ));
        __m256d row[4];
        for (int c = 0; c < 3; ++c) row[c] = _mm256_and_pd(within, _mm256_load_pd(&t.force[c][k]));
        __m256d twist[3] = {zero, zero, zero};
        if constexpr (Phys::kRotation) {
          for (int c = 0; c < 3; ++c) {
            twist[c] = _mm256_and_pd(touching, _mm256_load_pd(&t.twist[c][k]));
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
          __m256d spring[4];
          for (int c = 0; c < 3; ++c) {
            spring[c] = _mm256_and_pd(touching, _mm256_load_pd(&t.shear[c][k]));
          }
          spring[3] = zero;
          Transpose4(spring[0], spring[1], spring[2], spring[3]);
          for (int q = 0; q < 4; ++q) {
            double* record = shear_out + 3 * (k + q);
            _mm_storeu_pd(record, _mm256_castpd256_pd128(spring[q]));
            _mm_store_sd(record + 2, _mm256_extractf128_pd(spring[q], 1));
          }
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
  [[gnu::always_inline]] inline void DenseGather(Scratch& t, std::int64_t b, int k, int n) const {
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
      double d2 = 0;
      for (int c = 0; c < Dim; ++c) {
        const double d = particle_i.position_radius.v[c] - particle_j.position_radius.v[c];
        t.normal[c][k] = d;
        d2 += d * d;
      }
      const double cutoff_m = r_i + r_j + cutoff_gap_m;
      t.within[k] = d2 < cutoff_m * cutoff_m ? 1.0 : 0.0;
      t.radius_i[k] = r_i;
      t.radius_j[k] = r_j;
      t.mass_i[k] = particle_i.velocity_mass.s;
      t.mass_j[k] = particle_j.velocity_mass.s;
      for (int c = 0; c < Dim; ++c)
        t.velocity[c][k] = particle_i.velocity_mass.v[c] - particle_j.velocity_mass.v[c];
      if constexpr (Phys::kRotation) {
        if constexpr (Dim == 3) {
          for (int c = 0; c < 3; ++c)
            t.spin[c][k] = r_i * particle_i.spin_inertia.w[c] + r_j * particle_j.spin_inertia.w[c];
        } else {
          t.spin[0][k] = r_i * particle_i.spin_inertia.w + r_j * particle_j.spin_inertia.w;
        }
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) t.shear[c][k] = shear[k][c];
      }
      t.pair[k] = static_cast<std::int32_t>(b + k);
    }
  }

  // Writes the results, springs and live flags of dense-block contacts k .. n-1; returns how
  // many interact.
  [[gnu::always_inline]] inline std::int64_t DenseScatter(const Scratch& t, std::int64_t b, int k,
                                                          int n) {
    auto* results = this->pair_result_.data() + b;
    V* shear_out = this->pair_shear_.data() + b;
    std::uint8_t* live = this->pair_live_.data() + b;
    std::int64_t interacting = 0;
    for (; k < n; ++k) {
      // A pair beyond the cutoff is zeroed whole, as the compacted pass clears it, even in
      // the last-ulp case where its overlap reads positive.
      const bool within = t.within[k] != 0;
      const bool touching = within & (t.overlap[k] > 0);
      for (int c = 0; c < Dim; ++c) results[k].force_n[c] = within ? t.force[c][k] : 0.0;
      if constexpr (Phys::kRotation) {
        if constexpr (Dim == 3) {
          for (int c = 0; c < 3; ++c) results[k].twist_n[c] = touching ? t.twist[c][k] : 0.0;
        } else {
          results[k].twist_n = touching ? t.twist[0][k] : 0.0;
        }
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) shear_out[k][c] = touching ? t.shear[c][k] : 0.0;
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
  std::int64_t PairRangeCompacted(Scratch& t, std::int64_t begin, std::int64_t end) {
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

  // A wall is a body of infinite mass and curvature radius: m_eff = m, R_eff = r. Its contacts
  // run through the pair stages (kWall), which take the normal and overlap from the wall's own
  // geometry instead of a centre distance; wall_result_ holds each (particle, wall) result.
  void WallRange(Scratch& t, std::int64_t begin, std::int64_t end) {
    const std::size_t wall_count = this->walls_.size();
    int count = 0;
    for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
      const std::uint64_t near = this->wall_near_[i];
      if (near == 0 && wall_count <= 64) continue;
      const Record& record = records_[i];
      const double r_i = record.position_radius.s;
      for (std::size_t w = 0; w < wall_count; ++w) {
        if (w < 64 && ((near >> w) & 1) == 0) continue;
        const std::size_t h = i * wall_count + w;
        V n;
        const double overlap = this->walls_[w].Overlap(record.position_radius.v, r_i, n);
        if (overlap <= 0) {
          wall_result_[h] = {V::Zero(), ZeroSpin<Dim>()};
          if constexpr (Phys::kTangential) this->wall_shear_[h] = V::Zero();
          if constexpr (Law::kNeedsHistory) this->wall_normal_history_[h] = NormalHistory{};
          continue;
        }
        t.pair[count] = static_cast<std::int32_t>(h);
        t.overlap[count] = overlap;
        t.radius_i[count] = r_i;
        t.mass_i[count] = record.velocity_mass.s;
        for (int c = 0; c < Dim; ++c) {
          t.normal[c][count] = n[c];
          t.velocity[c][count] = record.velocity_mass.v[c];
        }
        if constexpr (Phys::kRotation) {
          if constexpr (Dim == 3) {
            for (int c = 0; c < 3; ++c) t.spin[c][count] = r_i * record.spin_inertia.w[c];
          } else {
            t.spin[0][count] = r_i * record.spin_inertia.w;
          }
        }
        if constexpr (Phys::kTangential) {
          for (int c = 0; c < Dim; ++c) t.shear[c][count] = this->wall_shear_[h][c];
        }
        if (++count == kBlock) {
          WallBlock(kBlock, t);
          count = 0;
        }
      }
    }
    if (count > 0) WallBlock(count, t);
  }

  void WallBlock(int n, Scratch& t) {
    stages_.template Run<true>(simd_, t, n, this->wall_normal_history_);
    for (int k = 0; k < n; ++k) {
      const auto h = static_cast<std::size_t>(t.pair[k]);
      auto& result = wall_result_[h];
      for (int c = 0; c < Dim; ++c) result.force_n[c] = t.force[c][k];
      if constexpr (Phys::kRotation) {
        if constexpr (Dim == 3) {
          for (int c = 0; c < 3; ++c) result.twist_n[c] = t.twist[c][k];
        } else {
          result.twist_n = t.twist[0][k];
        }
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) this->wall_shear_[h][c] = t.shear[c][k];
      }
    }
  }

  // The forces of the first `n` pairs of the block (all closer than their cutoff; the distance
  // pass has filled in pair, normal = x_i - x_j and the radii); their whole pair_result_ is
  // written. The rest of the block is gathered from the particles, then the stages run over it
  // (contact_stages.h).
  void ContactBlock(int n, Scratch& t) {
    GatherBlock(n, t);
    stages_.template Run<false>(simd_, t, n, this->pair_normal_history_);
    ScatterBlock(n, t);
  }

  void GatherBlock(int n, Scratch& t) const {
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
            t.spin[c][k] =
                r_i * records_[i].spin_inertia.w[c] + r_j * records_[j].spin_inertia.w[c];
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

  void ScatterBlock(int n, const Scratch& t) {
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

  // Sum of the pair forces of particle i in a fixed order, plus walls, gravity and damping;
  // stored, and returned for the integrator.
  [[gnu::always_inline]] Load GatherForce(std::int32_t i) {
    const auto& pairs = this->pairs_;
    const double r_i = records_[static_cast<std::size_t>(i)].position_radius.s;
    V force = records_[static_cast<std::size_t>(i)].velocity_mass.s * gravity_;
    // Every pair's torque on i is -r_i (n x F_t): the twists are summed and scaled once.
    S twist = ZeroSpin<Dim>();
    const auto* results = this->pair_result_.data();
    for (std::int32_t p = pairs.begin[i]; p < pairs.begin[i + 1]; ++p) {
      force += results[p].force_n;
      if constexpr (Phys::kRotation) twist += results[p].twist_n;
    }
    for (std::int32_t k = pairs.reverse_begin[i]; k < pairs.reverse_begin[i + 1]; ++k) {
      const std::int32_t p = pairs.reverse_pairs[k];
      force -= results[p].force_n;
      if constexpr (Phys::kRotation) twist += results[p].twist_n;
    }
    const std::size_t wall_count = this->walls_.size();
    const std::uint64_t near = this->wall_near_[static_cast<std::size_t>(i)];
    for (std::size_t w = 0; w < wall_count; ++w) {
      if (w >= 64 || ((near >> w) & 1) != 0) {
        const PairResult& wall = wall_result_[static_cast<std::size_t>(i) * wall_count + w];
        force += wall.force_n;
        if constexpr (Phys::kRotation) twist += wall.twist_n;
      }
    }
    S torque = -r_i * twist;
    if constexpr (Phys::kLocalDamping) {
      const Record& record = records_[static_cast<std::size_t>(i)];
      ApplyLocalDamping<Dim, Phys::kRotation>(this->settings_.local_damping, record.velocity_mass.v,
                                              record.spin_inertia.w, force, torque);
    }
    return {force, torque};
  }

  ContactStages<Dim, Law, Phys> stages_;
  V gravity_;
  ContactSimd simd_;              // the build of the contact arithmetic (same results)
  std::vector<Scratch> scratch_;  // one per pool chunk
  std::vector<Record> records_;   // see LoadRecords
  // Force on the particle and n x F_t of each (particle, wall) contact, particle * walls + wall;
  // written every step for the walls a particle is near (WallRange), zero when not touching.
  std::vector<PairResult> wall_result_;
};

// Picks the physics flags at run time once, so each scene runs one specialised loop.
template <int Dim, class Law>
std::unique_ptr<EngineBase<Dim>> MakeEngineForLaw(const EngineSettings& settings,
                                                  std::vector<Wall<Dim>> walls, const Law& law,
                                                  const PhysicsSpec& physics) {
  auto make = [&](auto tangential, auto rotation, auto vdw, auto damping) {
    using P = Physics<decltype(tangential)::value, decltype(rotation)::value, decltype(vdw)::value,
                      decltype(damping)::value>;
    return std::unique_ptr<EngineBase<Dim>>(
        new Engine<Dim, Law, P>(settings, std::move(walls), law));
  };
  using T = std::true_type;
  using F = std::false_type;
  auto with_damping = [&](auto tangential, auto rotation, auto vdw) {
    return physics.local_damping ? make(tangential, rotation, vdw, T{})
                                 : make(tangential, rotation, vdw, F{});
  };
  auto with_vdw = [&](auto tangential, auto rotation) {
    return physics.van_der_waals ? with_damping(tangential, rotation, T{})
                                 : with_damping(tangential, rotation, F{});
  };
  if (!physics.tangential) return with_vdw(F{}, F{});
  return physics.rotation ? with_vdw(T{}, T{}) : with_vdw(T{}, F{});
}

template <int Dim>
std::unique_ptr<EngineBase<Dim>> MakeEngine(const EngineSettings& settings,
                                            std::vector<Wall<Dim>> walls,
                                            const ContactLawConfig& law,
                                            const PhysicsSpec& physics) {
  const auto evaluator = MakeContactLaw(law);
  return std::visit(
      [&](const auto& typed_law) {
        return MakeEngineForLaw<Dim>(settings, std::move(walls), typed_law, physics);
      },
      evaluator);
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_ENGINE_IMPL_H_
