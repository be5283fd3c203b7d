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
// The stages: geometry (unit normal, overlap, relative velocity, the spring turned into the
// tangent plane), the normal law (the only part that depends on the law), then the force: the
// tangential spring with its Coulomb cap and its twist (tangential_spring.h) and the van der
// Waals pull (van_der_waals.h). The engine's pair pass and wall contacts fill the blocks and
// write their results back.

#include <cmath>
#include <cstdint>
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
// arrays) so that the stages vectorise across contacts.
template <int Dim>
struct ContactScratch {
  static constexpr int kBlock = kContactBlock;
  static constexpr int kSpinDim = Dim == 3 ? 3 : 1;
  bool dense = false;          // how this chunk runs its pairs (see Engine::PairRangeDense)
  std::int32_t pair[kBlock];   // the pair's index, or the (particle, wall) slot of a wall contact
  std::int32_t first[kBlock];  // the pair's particles (compacted pair blocks)
  std::int32_t second[kBlock];
  alignas(32) double normal[Dim][kBlock];     // x_i - x_j, then the unit normal from j to i
  alignas(32) double velocity[Dim][kBlock];   // v_i - v_j, then the tangential relative velocity
  alignas(32) double spin[kSpinDim][kBlock];  // r_i w_i + r_j w_j
  alignas(32) double shear[Dim][kBlock];
  alignas(32) double force[Dim][kBlock];
  alignas(32) double twist[kSpinDim][kBlock];
  alignas(32) double radius_i[kBlock];
  alignas(32) double within[kBlock];  // dense blocks: 1 when closer than the cutoff, else 0
  alignas(32) double radius_j[kBlock];
  alignas(32) double mass_i[kBlock];
  alignas(32) double mass_j[kBlock];
  alignas(32) double overlap[kBlock];
  alignas(32) double overlap_rate[kBlock];
  alignas(32) double normal_force[kBlock];
  alignas(32) double shear_factor[kBlock];
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
        spring_{settings.time_step_s, settings.tangential_stiffness_n_per_m,
                1.0 / -settings.tangential_stiffness_n_per_m},
        friction_(settings.friction),
        wall_friction_(settings.wall_friction),
        hamaker_j_(settings.hamaker_j),
        vdw_min_gap_m_(settings.vdw_min_gap_m) {}

  // The force, twist and spring of the first n contacts of t, by the given build. `history` is
  // the normal history the contacts' t.pair indexes (of the pairs or of the wall contacts); only
  // a law that keeps one reads or writes it.
  template <bool kWall>
  void Run(ContactSimd simd, Scratch& t, int n, std::vector<NormalHistory>& history) const {
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
    switch (simd) {
      case ContactSimd::kAvx512:
        RunAvx512<kWall>(t, n, history);
        break;
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

  // The same arithmetic inlined into the caller, for a caller compiled for one build (the dense
  // pair blocks). The three builds are compiled from this one source.
  template <bool kWall>
  [[gnu::always_inline]] inline void Arithmetic(Scratch& t, int n,
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
  template <bool kWall>
  void RunBaseline(Scratch& t, int n, std::vector<NormalHistory>& history) const {
    Arithmetic<kWall>(t, n, history);
  }
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
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

  // Stage 1: geometry, relative velocity and the spring projected into the tangent plane. A wall
  // contact arrives with its unit normal, overlap, v_i and r_i w_i already in place (the wall
  // is at rest).
  template <bool kWall>
  [[gnu::always_inline]] inline void GeometryStage(Scratch& t, int n) const {
    for (int k = 0; k < n; ++k) {
      double nv[Dim];
      if constexpr (kWall) {
        for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k];
      } else {
        double d[Dim];
        for (int c = 0; c < Dim; ++c) d[c] = t.normal[c][k];
        const double dist = std::sqrt(SumOfSquares<Dim>(d));
        const double inverse = 1.0 / dist;
        for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k] * inverse;
        t.overlap[k] = (t.radius_i[k] + t.radius_j[k]) - dist;
      }
      double v_rel[Dim];
      for (int c = 0; c < Dim; ++c) v_rel[c] = t.velocity[c][k];
      if constexpr (Phys::kRotation) {
        // v_rel -= spin x n
        if constexpr (Dim == 3) {
          const double w0 = t.spin[0][k];
          const double w1 = t.spin[1][k];
          const double w2 = t.spin[2][k];
          v_rel[0] -= w1 * nv[2] - w2 * nv[1];
          v_rel[1] -= w2 * nv[0] - w0 * nv[2];
          v_rel[2] -= w0 * nv[1] - w1 * nv[0];
        } else {
          const double w = t.spin[0][k];
          v_rel[0] -= -w * nv[1];
          v_rel[1] -= w * nv[0];
        }
      }
      double v_n = 0;
      for (int c = 0; c < Dim; ++c) v_n += v_rel[c] * nv[c];
      t.overlap_rate[k] = -v_n;
      for (int c = 0; c < Dim; ++c) {
        t.normal[c][k] = nv[c];
        t.velocity[c][k] = v_rel[c] - v_n * nv[c];
      }
      if constexpr (Phys::kTangential) {
        // The spring turned into the current tangent plane; the factor restoring its length is
        // applied in stage 3.
        double spring[Dim];
        for (int c = 0; c < Dim; ++c) spring[c] = t.shear[c][k];
        t.shear_factor[k] = ProjectSpring<Dim>(spring, nv);
        for (int c = 0; c < Dim; ++c) t.shear[c][k] = spring[c];
      }
    }
  }

  // The law's view of block contact k: reduced mass and effective radius of the pair. A wall is
  // a body of infinite mass and curvature radius: m_eff = m, R_eff = r.
  template <bool kWall>
  [[gnu::always_inline]] static inline NormalContact ContactAt(const Scratch& t, int k) {
    if constexpr (kWall) return {t.overlap[k], t.overlap_rate[k], t.mass_i[k], t.radius_i[k]};
    const double r_i = t.radius_i[k];
    const double r_j = t.radius_j[k];
    const double m_i = t.mass_i[k];
    const double m_j = t.mass_j[k];
    return {t.overlap[k], t.overlap_rate[k], m_i * m_j / (m_i + m_j), r_i * r_j / (r_i + r_j)};
  }

  // Stage 2: the normal law. A separate loop, so a law that does not vectorise does not stop
  // the stages around it. Every contact is evaluated; the non-touching ones are dropped in
  // stage 3 (the laws return 0 or a value that is discarded for them).
  template <bool kWall>
  [[gnu::always_inline]] inline void NormalForceStage(Scratch& t, int n) const {
    {
      // Copies of members: loaded once, not through `this` (which might alias t) per contact,
      // which would stop the vectoriser.
      const Law law = law_;
      for (int k = 0; k < n; ++k) {
        NormalHistory none{};
        t.normal_force[k] = law.NormalForce(ContactAt<kWall>(t, k), none);
      }
    }
  }

  // A law with a per-contact history (walton-braun-plastic) runs one touching contact at a time.
  template <bool kWall>
  void NormalForcesWithHistory(Scratch& t, int n, std::vector<NormalHistory>& history) const {
    for (int k = 0; k < n; ++k) {
      t.normal_force[k] = 0;
      if (!(t.overlap[k] > 0)) continue;
      t.normal_force[k] =
          law_.NormalForce(ContactAt<kWall>(t, k), history[static_cast<std::size_t>(t.pair[k])]);
    }
  }

  // Stage 3: the tangential spring with its Coulomb cap, the contact force and its twist, and
  // the van der Waals pull.
  template <bool kWall>
  [[gnu::always_inline]] inline void ForceStage(Scratch& t, int n) const {
    const SpringConstants spring_constants = spring_;
    const double friction = kWall ? wall_friction_ : friction_;
    const double hamaker_j = hamaker_j_;
    const double min_gap_m = vdw_min_gap_m_;
    for (int k = 0; k < n; ++k) {
      const double normal_force = t.normal_force[k];
      double force[Dim];
      for (int c = 0; c < Dim; ++c) force[c] = normal_force * t.normal[c][k];
      if constexpr (Phys::kTangential) {
        double spring[Dim];
        double tangential_velocity[Dim];
        for (int c = 0; c < Dim; ++c) {
          spring[c] = t.shear[c][k];
          tangential_velocity[c] = t.velocity[c][k];
        }
        double tangential[Dim];
        CoulombSpringForce<Dim>(spring, t.shear_factor[k], tangential_velocity, normal_force,
                                friction, spring_constants, tangential);
        for (int c = 0; c < Dim; ++c) {
          t.shear[c][k] = spring[c];
          force[c] += tangential[c];
        }
        if constexpr (Phys::kRotation) {
          double nv[Dim];
          for (int c = 0; c < Dim; ++c) nv[c] = t.normal[c][k];
          double twist[kSpinDim];
          SpringTwist<Dim>(nv, tangential, twist);
          for (int c = 0; c < kSpinDim; ++c) t.twist[c][k] = twist[c];
        }
      }
      // A pair within the van der Waals cutoff but not touching feels only the attraction.
      const bool touching = t.overlap[k] > 0;
      for (int c = 0; c < Dim; ++c) force[c] = touching ? force[c] : 0.0;
      if constexpr (Phys::kVanDerWaals && !kWall) {
        const double r_i = t.radius_i[k];
        const double r_j = t.radius_j[k];
        const double effective_radius_m = r_i * r_j / (r_i + r_j);
        const double attraction =
            VanDerWaalsForceN(t.overlap[k], effective_radius_m, hamaker_j, min_gap_m);
        for (int c = 0; c < Dim; ++c) force[c] -= attraction * t.normal[c][k];
      }
      for (int c = 0; c < Dim; ++c) t.force[c][k] = force[c];
    }
  }

  Law law_;
  SpringConstants spring_;
  double friction_;
  double wall_friction_;
  double hamaker_j_;
  double vdw_min_gap_m_;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_CONTACT_STAGES_H_
