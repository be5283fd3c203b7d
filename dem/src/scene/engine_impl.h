#ifndef BOUNCECAL_DEM_SCENE_ENGINE_IMPL_H_
#define BOUNCECAL_DEM_SCENE_ENGINE_IMPL_H_

// The force loop and integrator, templated on dimension, normal contact law and physics. Only
// the engine factories include this file.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <variant>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "scene/engine.h"

namespace bouncecal::dem::scene {

template <int Dim, class Law, class Phys>
class Engine final : public EngineBase<Dim> {
  static_assert(!Phys::kRotation || Phys::kTangential,
                "only the tangential force makes torque (paper 000 eq. 2)");

 public:
  Engine(const EngineSettings& settings, std::vector<Wall<Dim>> walls, Law law)
      : EngineBase<Dim>(settings, std::move(walls)),
        law_(std::move(law)),
        gravity_(this->Gravity()),
        shear_per_force_m_per_n_(1.0 / -settings.tangential_stiffness_n_per_m),
        scratch_(static_cast<std::size_t>(this->pool_->threads())) {}

  void ComputeForces() override {
    this->EnterWorkingOrder();
    ForcesInWorkingOrder();
    this->LeaveWorkingOrder();
  }

  void Advance(std::int64_t steps) override {
    if (steps <= 0) return;
    this->EnterWorkingOrder();
    if (!this->forces_valid_) ForcesInWorkingOrder();
    const std::int32_t n = this->state_.size();
    const double dt = this->settings_.time_step_s;
    const double half_dt = 0.5 * dt;
    auto& pool = *this->pool_;
    std::vector<double> chunk_move2(static_cast<std::size_t>(pool.threads()), 0.0);
    // Velocity Verlet (Verlet 1967; Allen & Tildesley ch. 3) with the closing half kick of one
    // step fused into the opening half kick and drift of the next, so a step costs two passes.
    auto kick_drift = [&](int chunk, std::int64_t begin, std::int64_t end) {
      double move2 = 0;
      for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
        move2 = std::max(move2, KickDrift(i, half_dt));
      }
      chunk_move2[static_cast<std::size_t>(chunk)] = move2;
    };
    pool.ParallelFor(n, kick_drift);
    for (std::int64_t step = 0; step < steps; ++step) {
      double max_move2 = 0;  // max is exact, so the order of the chunks does not matter
      for (double m : chunk_move2) max_move2 = std::max(max_move2, m);
      if (!this->settings_.brute_force_pairs && 4 * max_move2 > Square(this->settings_.skin_m)) {
        this->pairs_valid_ = false;
      }
      PrepareStep();
      if (this->settings_.stop_at_first_contact) this->StopFirstContacts();
      PairForces();
      const bool last = step + 1 == steps;
      std::fill(chunk_move2.begin(), chunk_move2.end(), 0.0);
      pool.ParallelFor(n, [&](int chunk, std::int64_t begin, std::int64_t end) {
        double move2 = 0;
        for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
          GatherForce(i);
          if (last) {
            HalfKick(i, half_dt);
          } else {
            move2 = std::max(move2, KickDrift(i, dt));
          }
        }
        chunk_move2[static_cast<std::size_t>(chunk)] = move2;
      });
      ++this->steps_;
    }
    this->forces_valid_ = true;
    this->LeaveWorkingOrder();
  }

 private:
  using V = Vec<Dim>;
  using S = Spin<Dim>;
  static double Square(double x) { return x * x; }

  void ForcesInWorkingOrder() {
    PrepareStep();
    PairForces();
    const std::int32_t n = this->state_.size();
    for (std::int32_t i = 0; i < n; ++i) GatherForce(i);
    this->forces_valid_ = true;
  }

  void PrepareStep() {
    if (!this->pairs_valid_) {
      this->RebuildPairs(this->PairReachM(Phys::kVanDerWaals));
    }
  }

  // v(t + dt/2) = v + kick a; x += dt v. Returns the squared distance moved since the last
  // neighbour-list build.
  double KickDrift(std::int32_t i, double kick) {
    auto& s = this->state_;
    s.velocity_mps[i] += (kick * s.inverse_mass[i]) * s.force_n[i];
    if constexpr (Phys::kRotation) {
      s.angular_velocity_radps[i] += (kick * s.inverse_inertia[i]) * s.torque_nm[i];
    }
    s.position_m[i] += this->settings_.time_step_s * s.velocity_mps[i];
    return (s.position_m[i] - this->position_at_rebuild_[i]).squaredNorm();
  }

  void HalfKick(std::int32_t i, double half_dt) {
    auto& s = this->state_;
    s.velocity_mps[i] += (half_dt * s.inverse_mass[i]) * s.force_n[i];
    if constexpr (Phys::kRotation) {
      s.angular_velocity_radps[i] += (half_dt * s.inverse_inertia[i]) * s.torque_nm[i];
    }
  }

  // Cundall & Strack (1979) tangential spring on the accumulated tangential displacement,
  // capped by Coulomb friction (paper 000 eq. 5-6). The spring is first rotated into the current
  // tangent plane with its length kept, so a rolling contact does not grow a normal component
  // (LAMMPS gran/hooke/history projects without the rescale; pair granular rescales like this).
  // When it slides the spring is reset to the Coulomb force, so |F_t| never exceeds mu |F_n|.
  // Split in two around the rescale factor so the pair kernel can take the square roots of a
  // whole block of contacts at once (see PairForces).
  //
  // Projects the spring into the tangent plane; old2 and new2 are its squared lengths before and
  // after, or both 1 when there is nothing to rescale.
  static void ProjectShear(V& shear, const V& n, double& old2, double& new2) {
    old2 = shear.squaredNorm();
    new2 = 1;
    if (old2 > 0) {
      shear -= shear.dot(n) * n;
      new2 = shear.squaredNorm();
    }
    if (!(old2 > 0 && new2 > 0)) old2 = new2 = 1;  // sqrt(1 / 1) = 1 leaves the spring as is
  }

  // Rescales by `factor` = sqrt(old2 / new2), adds v_t dt and applies the Coulomb cap. Returns
  // the force on the body whose relative velocity vt is.
  V FinishShear(V& shear, double factor, const V& vt, double normal_force_n,
                double friction) const {
    shear *= factor;
    shear += this->settings_.time_step_s * vt;
    const double ks = this->settings_.tangential_stiffness_n_per_m;
    V force = -ks * shear;
    const double cap = friction * std::abs(normal_force_n);
    const double f2 = force.squaredNorm();
    if (f2 > cap * cap) {
      force *= cap / std::sqrt(f2);
      shear = force * shear_per_force_m_per_n_;  // = force / -ks, the division taken once
    }
    return force;
  }

  V TangentialForce(V& shear, const V& n, const V& vt, double normal_force_n,
                    double friction) const {
    double old2;
    double new2;
    ProjectShear(shear, n, old2, new2);
    return FinishShear(shear, std::sqrt(old2 / new2), vt, normal_force_n, friction);
  }

  // Each chunk of the pair list runs in stages. The first only measures distances (most listed
  // pairs are within the skin but not touching), zeroes their results and collects the pairs
  // that interact, without a data-dependent branch. The interacting pairs then go through the
  // contact laws in blocks of kBlock, stage by stage: a contact is one long chain of dependent
  // square roots and divisions, so each chain is cut where it needs one and the square roots
  // and divisions of the whole block are taken together (independent, so they overlap in the
  // pipeline, two per SSE2 instruction). The arithmetic of each pair is the same as a one-pass
  // loop and does not depend on the chunking: results are the same for every thread count.
  void PairForces() {
    this->pool_->ParallelFor(
        static_cast<std::int64_t>(this->pairs_.size()),
        [this](int chunk, std::int64_t begin, std::int64_t end) {
          const auto& x = this->state_.position_m;
          const std::int32_t* first = this->pairs_.first.data();
          const std::int32_t* second = this->pairs_.second.data();
          const double* radius = this->state_.radius_m.data();
          // Pair terms are recomputed from the particles rather than stored per pair, to keep
          // the per-pair arrays (read every step) small.
          const double cutoff_gap_m = Phys::kVanDerWaals ? this->settings_.vdw_cutoff_gap_m : 0.0;
          auto* results = this->pair_result_.data();
          std::int32_t* contacts = this->chunk_contacts_[static_cast<std::size_t>(chunk)].data();
          std::int64_t count = 0;
          for (std::int64_t p = begin; p < end; ++p) {
            const std::int32_t i = first[p];
            const std::int32_t j = second[p];
            const V d = x[i] - x[j];
            const double cutoff_m = radius[i] + radius[j] + cutoff_gap_m;
            const bool interacts = d.squaredNorm() < cutoff_m * cutoff_m;
            results[p] = {V::Zero(), ZeroSpin<Dim>()};
            contacts[count] = static_cast<std::int32_t>(p);
            count += interacts ? 1 : 0;
            if constexpr (Phys::kTangential) {
              // The spring of a pair that does not touch is almost always zero already: test
              // for the rare one to clear (a predictable branch) instead of writing every one.
              // `&`, not `&&`: whether a listed pair touches is random, so a short-circuit jump
              // on it would be mispredicted about every third pair.
              auto& shear = this->pair_shear_[static_cast<std::size_t>(p)];
              if (!interacts & NonZeroBits(shear)) shear = V::Zero();
            }
            if constexpr (Law::kNeedsHistory) {
              if (!interacts) this->pair_normal_history_[static_cast<std::size_t>(p)] = {};
            }
          }
          auto& scratch = scratch_[static_cast<std::size_t>(chunk)];
          for (std::int64_t b = 0; b < count; b += kBlock) {
            ContactBlock(contacts + b, static_cast<int>(std::min<std::int64_t>(kBlock, count - b)),
                         scratch);
          }
        });
  }

  static constexpr int kBlock = 64;
  // Per-thread temporaries of one block of contacts.
  struct Scratch {
    alignas(16) double dist[kBlock];
    alignas(16) double inverse[kBlock];
    alignas(16) double old2[kBlock];
    alignas(16) double new2[kBlock];
    V normal[kBlock];
    V tangential_velocity[kBlock];
    double normal_force[kBlock];
    double overlap[kBlock];
    double effective_radius[kBlock];
    bool touching[kBlock];
  };

  // out[k] = sqrt(a[k] / b[k]) (b null: sqrt(a[k])), and inverse[k] = 1 / out[k] when asked.
  // Correctly rounded like the scalar std::sqrt and division, so results do not depend on the
  // block split. n is padded to even with harmless values by the caller.
  static void BlockSqrt(double* out, const double* a, const double* b, double* inverse, int n) {
#if defined(__SSE2__)
    for (int k = 0; k < n; k += 2) {
      __m128d v = _mm_load_pd(a + k);
      if (b != nullptr) v = _mm_div_pd(v, _mm_load_pd(b + k));
      v = _mm_sqrt_pd(v);
      _mm_store_pd(out + k, v);
      if (inverse != nullptr) _mm_store_pd(inverse + k, _mm_div_pd(_mm_set1_pd(1.0), v));
    }
#else
    for (int k = 0; k < n; ++k) {
      out[k] = std::sqrt(b != nullptr ? a[k] / b[k] : a[k]);
      if (inverse != nullptr) inverse[k] = 1.0 / out[k];
    }
#endif
  }

  // True unless every component is +0.0 (evaluated without branches).
  static bool NonZeroBits(const V& v) {
    std::uint64_t bits = 0;
    for (int c = 0; c < Dim; ++c) bits |= std::bit_cast<std::uint64_t>(v[c]);
    return bits != 0;
  }
  struct PairTerms {
    double radius_sum_m;
    double mass_kg;   // effective mass m_i m_j / (m_i + m_j)
    double radius_m;  // effective radius r_i r_j / (r_i + r_j)
  };
  PairTerms Terms(std::int32_t i, std::int32_t j) const {
    const auto& s = this->state_;
    const double r_i = s.radius_m[i];
    const double r_j = s.radius_m[j];
    const double m_i = s.mass_kg[i];
    const double m_j = s.mass_kg[j];
    return {r_i + r_j, m_i * m_j / (m_i + m_j), r_i * r_j / (r_i + r_j)};
  }

  // The forces of `n` pairs closer than their cutoff (their pair_result_ is zero on entry).
  void ContactBlock(const std::int32_t* contacts, int n, Scratch& t) {
    const auto& s = this->state_;
    const std::int32_t* first = this->pairs_.first.data();
    const std::int32_t* second = this->pairs_.second.data();
    const int padded = (n + 1) & ~1;
    // Stage 1: distances.
    for (int k = 0; k < n; ++k) {
      const std::int32_t p = contacts[k];
      t.normal[k] = s.position_m[first[p]] - s.position_m[second[p]];
      t.dist[k] = t.normal[k].squaredNorm();
    }
    if (padded > n) t.dist[n] = 1;
    BlockSqrt(t.dist, t.dist, nullptr, t.inverse, padded);
    // Stage 2: normal force, relative velocity and the projected spring.
    for (int k = 0; k < n; ++k) {
      const auto p = static_cast<std::size_t>(contacts[k]);
      const std::int32_t i = first[p];
      const std::int32_t j = second[p];
      const PairTerms terms = Terms(i, j);
      const V n_ij = t.normal[k] * t.inverse[k];  // from j to i; as d / dist
      t.normal[k] = n_ij;
      const double overlap = terms.radius_sum_m - t.dist[k];
      if constexpr (Phys::kVanDerWaals) {  // else R_eff is not used: skip its division
        t.overlap[k] = overlap;
        t.effective_radius[k] = terms.radius_m;
      }
      t.touching[k] = overlap > 0;
      t.old2[k] = 1;
      t.new2[k] = 1;
      auto& result = this->pair_result_[p];
      if (overlap > 0) {
        V v_rel = s.velocity_mps[i] - s.velocity_mps[j];
        if constexpr (Phys::kRotation) {
          const S spin = s.radius_m[i] * s.angular_velocity_radps[i] +
                         s.radius_m[j] * s.angular_velocity_radps[j];
          v_rel -= SpinCross(spin, n_ij);
        }
        const double v_n = v_rel.dot(n_ij);
        const NormalContact contact{overlap, -v_n, terms.mass_kg, terms.radius_m};
        const double normal_force = law_.NormalForce(contact, this->pair_normal_history_[p]);
        if constexpr (Phys::kTangential) {
          t.normal_force[k] = normal_force;
          t.tangential_velocity[k] = v_rel - v_n * n_ij;
          ProjectShear(this->pair_shear_[p], n_ij, t.old2[k], t.new2[k]);
        } else {
          result.force_n = normal_force * n_ij;
          AddVanDerWaals(result.force_n, overlap, terms.radius_m, n_ij);
        }
      } else {
        ResetPairHistory(p);
        AddVanDerWaals(result.force_n, overlap, terms.radius_m, n_ij);
      }
    }
    if constexpr (Phys::kTangential) {
      // Stage 3: the spring rescale factors, then the tangential force.
      if (padded > n) t.old2[n] = t.new2[n] = 1;
      BlockSqrt(t.old2, t.old2, t.new2, nullptr, padded);
      for (int k = 0; k < n; ++k) {
        if (!t.touching[k]) continue;
        const auto p = static_cast<std::size_t>(contacts[k]);
        const V& n_ij = t.normal[k];
        auto& result = this->pair_result_[p];
        const V tangential = FinishShear(this->pair_shear_[p], t.old2[k], t.tangential_velocity[k],
                                         t.normal_force[k], this->settings_.friction);
        V force = t.normal_force[k] * n_ij;
        force += tangential;
        if constexpr (Phys::kRotation) result.twist_n = TorqueCross(n_ij, tangential);
        AddVanDerWaals(force, t.overlap[k], t.effective_radius[k], n_ij);
        result.force_n = force;
      }
    }
  }

  // Hamaker (1937) sphere-sphere attraction for gaps h << R: F = A R_eff / (6 h^2), i.e.
  // A R / (12 h^2) for equal spheres (paper 004 eq. 2). It diverges at contact, so the gap is
  // floored at vdw_min_gap_m (an interatomic distance, Israelachvili ch. 13).
  void AddVanDerWaals(V& force, double overlap, double effective_radius_m, const V& n) const {
    if constexpr (Phys::kVanDerWaals) {
      const double gap = std::max(-overlap, this->settings_.vdw_min_gap_m);
      force -= (this->settings_.hamaker_j * effective_radius_m / (6 * gap * gap)) * n;
    }
  }

  void ResetPairHistory(std::size_t p) {
    if constexpr (Phys::kTangential) this->pair_shear_[p].setZero();
    if constexpr (Law::kNeedsHistory) this->pair_normal_history_[p] = NormalHistory{};
  }

  // Sum of the pair forces of particle i in a fixed order, plus walls, gravity and damping.
  void GatherForce(std::int32_t i) {
    auto& s = this->state_;
    const auto& pairs = this->pairs_;
    const double r_i = s.radius_m[i];
    V force = s.mass_kg[i] * gravity_;
    S torque = ZeroSpin<Dim>();
    const auto* results = this->pair_result_.data();
    for (std::int32_t p = pairs.begin[i]; p < pairs.begin[i + 1]; ++p) {
      force += results[p].force_n;
      if constexpr (Phys::kRotation) torque -= r_i * results[p].twist_n;
    }
    for (std::int32_t k = pairs.reverse_begin[i]; k < pairs.reverse_begin[i + 1]; ++k) {
      const std::int32_t p = pairs.reverse_pairs[k];
      force -= results[p].force_n;
      if constexpr (Phys::kRotation) torque -= r_i * results[p].twist_n;
    }
    const std::size_t wall_count = this->walls_.size();
    const std::uint64_t near = this->wall_near_[static_cast<std::size_t>(i)];
    for (std::size_t w = 0; w < wall_count; ++w) {
      if (w >= 64 || ((near >> w) & 1) != 0) WallForce(i, w, force, torque);
    }
    if constexpr (Phys::kLocalDamping) {
      // Cundall (1987) local non-viscous damping, as in paper 004 eq. 12: each component of the
      // unbalanced force is reduced by alpha |F| against the velocity. It removes kinetic
      // energy without a velocity scale and leaves the state at rest unchanged.
      const double alpha = this->settings_.local_damping;
      for (int d = 0; d < Dim; ++d) {
        const double v = s.velocity_mps[i][d];
        if (v != 0) force[d] -= alpha * std::abs(force[d]) * (v > 0 ? 1.0 : -1.0);
      }
      if constexpr (Phys::kRotation) {
        if constexpr (Dim == 3) {
          for (int d = 0; d < 3; ++d) {
            const double w = s.angular_velocity_radps[i][d];
            if (w != 0) torque[d] -= alpha * std::abs(torque[d]) * (w > 0 ? 1.0 : -1.0);
          }
        } else {
          const double w = s.angular_velocity_radps[i];
          if (w != 0) torque -= alpha * std::abs(torque) * (w > 0 ? 1.0 : -1.0);
        }
      }
    }
    s.force_n[i] = force;
    if constexpr (Phys::kRotation) s.torque_nm[i] = torque;
  }

  // A wall is a body of infinite mass and curvature radius: m_eff = m, R_eff = r.
  [[gnu::always_inline]] void WallForce(std::int32_t i, std::size_t w, V& force, S& torque) {
    auto& s = this->state_;
    const std::size_t h = static_cast<std::size_t>(i) * this->walls_.size() + w;
    V n;
    const double r_i = s.radius_m[i];
    const double overlap = this->walls_[w].Overlap(s.position_m[i], r_i, n);
    if (overlap <= 0) {
      if constexpr (Phys::kTangential) this->wall_shear_[h].setZero();
      if constexpr (Law::kNeedsHistory) this->wall_normal_history_[h] = NormalHistory{};
      return;
    }
    V v_rel = s.velocity_mps[i];
    if constexpr (Phys::kRotation) v_rel -= SpinCross(r_i * s.angular_velocity_radps[i], n);
    const double v_n = v_rel.dot(n);
    const NormalContact contact{overlap, -v_n, s.mass_kg[i], r_i};
    const double normal_force = law_.NormalForce(contact, this->wall_normal_history_[h]);
    force += normal_force * n;
    if constexpr (Phys::kTangential) {
      const V v_t = v_rel - v_n * n;
      const V tangential = TangentialForce(this->wall_shear_[h], n, v_t, normal_force,
                                           this->settings_.wall_friction);
      force += tangential;
      if constexpr (Phys::kRotation) torque -= r_i * TorqueCross(n, tangential);
    }
  }

  Law law_;
  V gravity_;
  double shear_per_force_m_per_n_;  // 1 / -k_t: the spring of a sliding contact from its force
  std::vector<Scratch> scratch_;    // one per pool chunk
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
