#ifndef BOUNCECAL_DEM_ENGINE_CONTACT_STAGES_H_
#define BOUNCECAL_DEM_ENGINE_CONTACT_STAGES_H_

// The contact arithmetic of the packing engine, shared by particle pairs and particle-wall
// contacts. A contact is one long chain of dependent square roots and divisions, so the engine
// gathers up to kContactBlock contacts into per-component arrays (ContactScratch, a structure of
// arrays) and each stage below runs over the whole block without branches: every contact takes
// every path and a select keeps the right value, so the compiler vectorises each stage (8
// contacts per instruction with AVX-512, 4 with AVX2, 2 with the baseline SSE2). Every stage is
// element-wise IEEE arithmetic in the same order as the scalar formula (no FMA contraction, no
// reassociation: see dem/CMakeLists.txt), so the results are bit-identical across the builds
// and do not depend on how contacts fall into blocks.
//
// The same stages also run in float (ContactScratch<Dim, float>) for the particle pairs when
// EngineSettings::single_precision_contacts asks for it: twice the contacts per instruction and
// cheaper square roots and divisions, at the price of float's rounding; the conversions at the
// gather and write-back ate most of the gain on the AVX-512 host (docs/packing.md, "Single
// precision: the speed/accuracy trade"). The pair pass converts at the gather and the write-back;
// positions, velocities, springs between steps, the force sums and the wall contacts stay
// double, and the normal law runs in double (the laws are written for it; it has no root or
// division in the shipped scenes' walton-braun).
//
// The stages: geometry (unit normal, overlap, relative velocity, the spring turned into the
// tangent plane), the normal law (the only part that depends on the law), then the force: the
// tangential spring with its Coulomb cap and its twist (tangential_spring.h) and the van der
// Waals pull (van_der_waals.h). The engine's pair pass and wall contacts fill the blocks and
// write their results back.

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "bouncecal/dem/contact_laws.h"
#include "engine/engine.h"
#include "engine/simd_helpers.h"
#include "engine/tangential_spring.h"
#include "engine/van_der_waals.h"

namespace bouncecal::dem::scene {

inline constexpr int kContactBlock = 64;

// Per-thread temporaries of one block of contacts, one array per component (structure of
// arrays) so that the stages vectorise across contacts. Real: the precision of the arithmetic
// (float only for the pair blocks of single-precision contacts).
template <int Dim, class Real = double>
struct ContactScratch {
  static constexpr int kBlock = kContactBlock;
  static constexpr int kSpinDim = Dim == 3 ? 3 : 1;
  static constexpr bool kSingle = std::is_same_v<Real, float>;
  bool dense = false;          // how this chunk runs its pairs (see Engine::PairRangeDense)
  std::int32_t pair[kBlock];   // the pair's index, or the (particle, wall) slot of a wall contact
  std::int32_t first[kBlock];  // the pair's particles (compacted pair blocks)
  std::int32_t second[kBlock];
  alignas(32) Real normal[Dim][kBlock];     // x_i - x_j, then the unit normal from j to i
  alignas(32) Real velocity[Dim][kBlock];   // v_i - v_j, then the tangential relative velocity
  alignas(32) Real spin[kSpinDim][kBlock];  // r_i w_i + r_j w_j
  alignas(32) Real shear[Dim][kBlock];
  alignas(32) Real force[Dim][kBlock];
  alignas(32) Real twist[kSpinDim][kBlock];
  alignas(32) Real radius_i[kBlock];
  alignas(32) Real within[kBlock];  // dense blocks: 1 when closer than the cutoff, else 0
  alignas(32) Real radius_j[kBlock];
  alignas(32) Real mass_i[kBlock];
  alignas(32) Real mass_j[kBlock];
  alignas(32) Real overlap[kBlock];
  alignas(32) Real overlap_rate[kBlock];
  alignas(32) Real normal_force[kBlock];
  alignas(32) Real shear_factor[kBlock];
  // Single precision only: (r_i + r_j)^2 - |x_i - x_j|^2, taken in double by the gather. In
  // float, r_i + r_j - |x_i - x_j| would lose the overlap (about 1e-8 m under a few weights in
  // paper 000) to the rounding of the distance (float's spacing at 1 cm is 9e-10 m); this
  // difference of squares keeps it to float's relative precision (GeometryStage).
  alignas(32) Real square_gap[kSingle ? kBlock : 1];
  // With single-precision contacts, in a chunk's double block: the chunk's float block, which its
  // dense blocks run in and its compacted blocks are converted into (ContactStages::RunSingle);
  // null otherwise.
  ContactScratch<Dim, float>* single = nullptr;
};

// The stages for one normal law and physics (Physics<...> in engine.h), with the constants of a
// run. kWall: the block holds particle-wall contacts, whose normal and overlap come from the
// wall's geometry instead of a centre distance.
template <int Dim, class Law, class Phys>
class ContactStages {
 public:
  using Scratch = ContactScratch<Dim>;
  static constexpr int kSpinDim = Scratch::kSpinDim;

  ContactStages(Law law, const EngineSettings& settings)
      : law_(std::move(law)),
        double_(ConstantsFor<double>(settings)),
        single_(ConstantsFor<float>(settings)) {}

  // The force, twist and spring of the first n contacts of t, by the given build. `history` is
  // the normal history the contacts' t.pair indexes (of the pairs or of the wall contacts); only
  // a law that keeps one reads or writes it.
  template <bool kWall>
  void Run(ContactSimd simd, Scratch& t, int n, std::vector<NormalHistory>& history) const {
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
    switch (simd) {
      case ContactSimd::kAvx512:
#if BOUNCECAL_SCENE_HAS_AVX512_PATH
        RunAvx512<kWall>(t, n, history);
        break;
#endif
      case ContactSimd::kAvx2:
        RunAvx2<kWall>(t, n, history);
        break;
      case ContactSimd::kBaseline:
        RunBaseline<kWall>(t, n, history);
        break;
    }
#else
    (void)simd;
    RunBaseline<kWall>(t, n, history);
#endif
  }

  // A block of pairs gathered in double (the compacted pair blocks) with single-precision
  // contacts: converted into t.single as the dense gather converts, the float stages, and the
  // results converted back into t. Every pair then gets the same float arithmetic whether its
  // chunk ran dense or compacted, a choice that depends on how the pairs fall into chunks, hence
  // on the thread count (which must not change a bit).
  void RunSingle(ContactSimd simd, Scratch& t, int n, std::vector<NormalHistory>& history) const {
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
    switch (simd) {
      case ContactSimd::kAvx512:
#if BOUNCECAL_SCENE_HAS_AVX512_PATH
        RunSingleAvx512(t, n, history);
        break;
#endif
      case ContactSimd::kAvx2:
        RunSingleAvx2(t, n, history);
        break;
      case ContactSimd::kBaseline:
        SingleArithmetic(t, n, history);
        break;
    }
#else
    (void)simd;
    SingleArithmetic(t, n, history);
#endif
  }

  // The same arithmetic inlined into the caller, for a caller compiled for one build (the dense
  // pair blocks). The three builds are compiled from this one source.
  template <bool kWall, class Real>
  [[gnu::always_inline]] inline void Arithmetic(ContactScratch<Dim, Real>& t, int n,
                                                std::vector<NormalHistory>& history) const {
    GeometryStage<kWall>(t, n);
    if constexpr (Law::kNeedsHistory) {
      NormalForcesWithHistory<kWall>(t, n, history);
    } else {
      NormalForceStage<kWall>(t, n);
    }
    ForceStage<kWall>(t, n);
  }

 private:
  // The run's constants in the precision of the arithmetic.
  template <class Real>
  struct Constants {
    BasicSpringConstants<Real> spring;
    Real friction;
    Real wall_friction;
    Real hamaker_j;
    Real vdw_min_gap_m;
  };
  template <class Real>
  static Constants<Real> ConstantsFor(const EngineSettings& s) {
    // 1 / -k_t is taken in double and then rounded, as every other constant.
    return {{static_cast<Real>(s.time_step_s), static_cast<Real>(s.tangential_stiffness_n_per_m),
             static_cast<Real>(1.0 / -s.tangential_stiffness_n_per_m)},
            static_cast<Real>(s.friction),
            static_cast<Real>(s.wall_friction),
            static_cast<Real>(s.hamaker_j),
            static_cast<Real>(s.vdw_min_gap_m)};
  }
  template <class Real>
  const Constants<Real>& ConstantsOf() const {
    if constexpr (std::is_same_v<Real, float>) {
      return single_;
    } else {
      return double_;
    }
  }

  template <bool kWall>
  void RunBaseline(Scratch& t, int n, std::vector<NormalHistory>& history) const {
    Arithmetic<kWall>(t, n, history);
  }
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
  [[gnu::target("avx2")]] void RunSingleAvx2(Scratch& t, int n,
                                             std::vector<NormalHistory>& history) const {
    SingleArithmetic(t, n, history);
  }
  [[BOUNCECAL_SCENE_AVX512]] void RunSingleAvx512(Scratch& t, int n,
                                                  std::vector<NormalHistory>& history) const {
    SingleArithmetic(t, n, history);
  }
  template <bool kWall>
  [[gnu::target("avx2")]] void RunAvx2(Scratch& t, int n,
                                       std::vector<NormalHistory>& history) const {
    Arithmetic<kWall>(t, n, history);
  }
  template <bool kWall>
  [[BOUNCECAL_SCENE_AVX512]] void RunAvx512(Scratch& t, int n,
                                            std::vector<NormalHistory>& history) const {
    Arithmetic<kWall>(t, n, history);
  }
#endif

  // See RunSingle. The values converted are those of the dense gather, by the same double
  // operations (the difference of squares as in Engine::DenseGather).
  [[gnu::always_inline]] inline void SingleArithmetic(Scratch& t, int n,
                                                      std::vector<NormalHistory>& history) const {
    ContactScratch<Dim, float>& f = *t.single;
    for (int k = 0; k < n; ++k) {
      double d[Dim];
      for (int c = 0; c < Dim; ++c) {
        d[c] = t.normal[c][k];
        f.normal[c][k] = static_cast<float>(d[c]);
        f.velocity[c][k] = static_cast<float>(t.velocity[c][k]);
      }
      const double d2 = SumOfSquares<Dim>(d);
      const double touch = t.radius_i[k] + t.radius_j[k];
      f.square_gap[k] = static_cast<float>(touch * touch - d2);
      f.radius_i[k] = static_cast<float>(t.radius_i[k]);
      f.radius_j[k] = static_cast<float>(t.radius_j[k]);
      f.mass_i[k] = static_cast<float>(t.mass_i[k]);
      f.mass_j[k] = static_cast<float>(t.mass_j[k]);
      if constexpr (Phys::kRotation) {
        for (int c = 0; c < kSpinDim; ++c) f.spin[c][k] = static_cast<float>(t.spin[c][k]);
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) f.shear[c][k] = static_cast<float>(t.shear[c][k]);
      }
      if constexpr (Law::kNeedsHistory) f.pair[k] = t.pair[k];
    }
    Arithmetic<false>(f, n, history);
    for (int k = 0; k < n; ++k) {
      t.overlap[k] = f.overlap[k];
      for (int c = 0; c < Dim; ++c) t.force[c][k] = f.force[c][k];
      if constexpr (Phys::kRotation) {
        for (int c = 0; c < kSpinDim; ++c) t.twist[c][k] = f.twist[c][k];
      }
      if constexpr (Phys::kTangential) {
        for (int c = 0; c < Dim; ++c) t.shear[c][k] = f.shear[c][k];
      }
    }
  }

  // Stage 1: geometry, relative velocity and the spring projected into the tangent plane. A wall
  // contact arrives with its unit normal, overlap, v_i and r_i w_i already in place (the wall
  // is at rest).
  template <bool kWall, class Real>
  [[gnu::always_inline]] inline void GeometryStage(ContactScratch<Dim, Real>& t, int n) const {
    for (int k = 0; k < n; ++k) {
      Real nv[Dim];
      if constexpr (kWall) {
        for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k];
      } else {
        Real d[Dim];
        for (int c = 0; c < Dim; ++c) d[c] = t.normal[c][k];
        const Real dist = std::sqrt(SumOfSquares<Dim>(d));
        const Real inverse = Real{1} / dist;
        for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k] * inverse;
        if constexpr (ContactScratch<Dim, Real>::kSingle) {
          // R - d = (R^2 - d^2) / (R + d): the difference of squares came from the gather in
          // double, so the overlap keeps float's relative precision (see square_gap).
          t.overlap[k] = t.square_gap[k] / ((t.radius_i[k] + t.radius_j[k]) + dist);
        } else {
          t.overlap[k] = (t.radius_i[k] + t.radius_j[k]) - dist;
        }
      }
      Real v_rel[Dim];
      for (int c = 0; c < Dim; ++c) v_rel[c] = t.velocity[c][k];
      if constexpr (Phys::kRotation) {
        // v_rel -= spin x n
        if constexpr (Dim == 3) {
          const Real w0 = t.spin[0][k];
          const Real w1 = t.spin[1][k];
          const Real w2 = t.spin[2][k];
          v_rel[0] -= w1 * nv[2] - w2 * nv[1];
          v_rel[1] -= w2 * nv[0] - w0 * nv[2];
          v_rel[2] -= w0 * nv[1] - w1 * nv[0];
        } else {
          const Real w = t.spin[0][k];
          v_rel[0] -= -w * nv[1];
          v_rel[1] -= w * nv[0];
        }
      }
      Real v_n = 0;
      for (int c = 0; c < Dim; ++c) v_n += v_rel[c] * nv[c];
      t.overlap_rate[k] = -v_n;
      for (int c = 0; c < Dim; ++c) {
        t.normal[c][k] = nv[c];
        t.velocity[c][k] = v_rel[c] - v_n * nv[c];
      }
      if constexpr (Phys::kTangential) {
        // The spring turned into the current tangent plane; the factor restoring its length is
        // applied in stage 3.
        Real spring[Dim];
        for (int c = 0; c < Dim; ++c) spring[c] = t.shear[c][k];
        t.shear_factor[k] = ProjectSpring<Dim>(spring, nv);
        for (int c = 0; c < Dim; ++c) t.shear[c][k] = spring[c];
      }
    }
  }

  // The law's view of block contact k: reduced mass and effective radius of the pair. A wall is
  // a body of infinite mass and curvature radius: m_eff = m, R_eff = r. In double whatever the
  // block's precision (the laws are double).
  template <bool kWall, class Real>
  [[gnu::always_inline]] static inline NormalContact ContactAt(const ContactScratch<Dim, Real>& t,
                                                               int k) {
    const double overlap = t.overlap[k];
    const double overlap_rate = t.overlap_rate[k];
    if constexpr (kWall) return {overlap, overlap_rate, t.mass_i[k], t.radius_i[k]};
    const double r_i = t.radius_i[k];
    const double r_j = t.radius_j[k];
    const double m_i = t.mass_i[k];
    const double m_j = t.mass_j[k];
    return {overlap, overlap_rate, m_i * m_j / (m_i + m_j), r_i * r_j / (r_i + r_j)};
  }

  // Stage 2: the normal law. A separate loop, so a law that does not vectorise does not stop
  // the stages around it. Every contact is evaluated; the non-touching ones are dropped in
  // stage 3 (the laws return 0 or a value that is discarded for them).
  template <bool kWall, class Real>
  [[gnu::always_inline]] inline void NormalForceStage(ContactScratch<Dim, Real>& t, int n) const {
    {
      // Copies of members: loaded once, not through `this` (which might alias t) per contact,
      // which would stop the vectoriser.
      const Law law = law_;
      for (int k = 0; k < n; ++k) {
        NormalHistory none{};
        t.normal_force[k] = static_cast<Real>(law.NormalForce(ContactAt<kWall>(t, k), none));
      }
    }
  }

  // A law with a per-contact history (walton-braun-plastic) runs one touching contact at a time.
  template <bool kWall, class Real>
  void NormalForcesWithHistory(ContactScratch<Dim, Real>& t, int n,
                               std::vector<NormalHistory>& history) const {
    for (int k = 0; k < n; ++k) {
      t.normal_force[k] = 0;
      if (!(t.overlap[k] > 0)) continue;
      t.normal_force[k] = static_cast<Real>(
          law_.NormalForce(ContactAt<kWall>(t, k), history[static_cast<std::size_t>(t.pair[k])]));
    }
  }

  // Stage 3: the tangential spring with its Coulomb cap, the contact force and its twist, and
  // the van der Waals pull.
  template <bool kWall, class Real>
  [[gnu::always_inline]] inline void ForceStage(ContactScratch<Dim, Real>& t, int n) const {
    const Constants<Real>& constants = ConstantsOf<Real>();
    const BasicSpringConstants<Real> spring_constants = constants.spring;
    const Real friction = kWall ? constants.wall_friction : constants.friction;
    const Real hamaker_j = constants.hamaker_j;
    const Real min_gap_m = constants.vdw_min_gap_m;
    for (int k = 0; k < n; ++k) {
      const Real normal_force = t.normal_force[k];
      Real force[Dim];
      for (int c = 0; c < Dim; ++c) force[c] = normal_force * t.normal[c][k];
      if constexpr (Phys::kTangential) {
        Real spring[Dim];
        Real tangential_velocity[Dim];
        for (int c = 0; c < Dim; ++c) {
          spring[c] = t.shear[c][k];
          tangential_velocity[c] = t.velocity[c][k];
        }
        Real tangential[Dim];
        CoulombSpringForce<Dim>(spring, t.shear_factor[k], tangential_velocity, normal_force,
                                friction, spring_constants, tangential);
        for (int c = 0; c < Dim; ++c) {
          t.shear[c][k] = spring[c];
          force[c] += tangential[c];
        }
        if constexpr (Phys::kRotation) {
          Real nv[Dim];
          for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k];
          Real twist[kSpinDim];
          SpringTwist<Dim>(nv, tangential, twist);
          for (int c = 0; c < kSpinDim; ++c) t.twist[c][k] = twist[c];
        }
      }
      // A pair within the van der Waals cutoff but not touching feels only the attraction.
      const bool touching = t.overlap[k] > 0;
      for (int c = 0; c < Dim; ++c) force[c] = touching ? force[c] : Real{0};
      if constexpr (Phys::kVanDerWaals && !kWall) {
        const Real r_i = t.radius_i[k];
        const Real r_j = t.radius_j[k];
        const Real effective_radius_m = r_i * r_j / (r_i + r_j);
        const Real attraction =
            VanDerWaalsForceN(t.overlap[k], effective_radius_m, hamaker_j, min_gap_m);
        for (int c = 0; c < Dim; ++c) force[c] -= attraction * t.normal[c][k];
      }
      for (int c = 0; c < Dim; ++c) t.force[c][k] = force[c];
    }
  }

  Law law_;
  Constants<double> double_;
  Constants<float> single_;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_CONTACT_STAGES_H_
