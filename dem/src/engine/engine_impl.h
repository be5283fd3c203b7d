#ifndef BOUNCECAL_DEM_ENGINE_ENGINE_IMPL_H_
#define BOUNCECAL_DEM_ENGINE_ENGINE_IMPL_H_

// The packing engine: Engine<Dim, Law, Phys> owns the stepping loop and ties its parts together,
// templated on dimension, normal contact law and physics so that each scene runs one loop
// specialised for it. Only the engine factories (engine_2d.cc, engine_3d.cc and their parts,
// engine_2d_part0.cc, ...) include this file;
// the parts are headers of the same translation unit, so the compiler sees every hot loop whole
// (no virtual call or std::function inside a step):
//   particle_records.h   the per-particle record the stepping loop works on
//   integrator.h         velocity Verlet's kick and drift on one record
//   engine_pair_pass.h   the pair pass, dense and compacted (members of Engine)
//   engine_walls.h       the particle-wall contacts (members of Engine)
//   contact_stages.h     the vectorised contact arithmetic over a block of contacts
//   tangential_spring.h  the Cundall-Strack spring with its Coulomb cap, and its twist
//   van_der_waals.h      the Hamaker attraction
//   local_damping.h      Cundall's local damping of a particle's load
//   simd_helpers.h       the x86 builds and the transposes of the dense pair pass
// State, pair list and contact history live in EngineBase (engine.h, engine_base.cc).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <variant>

#include "engine/contact_stages.h"
#include "engine/engine.h"
#include "engine/integrator.h"
#include "engine/local_damping.h"
#include "engine/particle_records.h"
#include "engine/simd_helpers.h"

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
        scratch_(static_cast<std::size_t>(this->pool_->chunks())),
        single_scratch_(settings.single_precision_contacts
                            ? static_cast<std::size_t>(this->pool_->chunks())
                            : 0) {
    for (std::size_t c = 0; c < single_scratch_.size(); ++c)
      scratch_[c].single = &single_scratch_[c];
  }

  void ComputeForces() override {
    this->DropPendingKick();  // the pending kick belongs to the forces of the stopped step
    this->EnterWorkingOrder();
    ForcesInWorkingOrder();
    this->LeaveWorkingOrder();
  }

  std::int64_t AdvanceUntil(std::int64_t steps, const std::function<bool()>& stop) override {
    if (steps <= 0) return 0;
    this->EnterWorkingOrder();
    if (!this->forces_valid_) {
      this->DropPendingKick();
      ForcesInWorkingOrder();
    } else {
      LoadRecords();
    }
    const std::int32_t n = this->state_.size();
    const double dt = this->settings_.time_step_s;
    const double half_dt = 0.5 * dt;
    // After a stopped Advance: the whole kick the uninterrupted run takes, from the velocities
    // it takes it from.
    double opening_kick = half_dt;
    if (this->kick_pending()) {
      for (std::int32_t i = 0; i < n; ++i) {
        records_[i].velocity_mass.v = this->pending_velocity_[i];
        if constexpr (Phys::kRotation) records_[i].spin_inertia.w = this->pending_spin_[i];
      }
      this->DropPendingKick();
      opening_kick = dt;
    }
    auto& pool = *this->pool_;
    std::vector<double> chunk_move2(static_cast<std::size_t>(pool.chunks()), 0.0);
    // Velocity Verlet with the closing half kick of one step fused into the opening half kick
    // and drift of the next, so a step costs two passes (integrator.h).
    auto kick_drift = [&](int chunk, std::int64_t begin, std::int64_t end) {
      double move2 = 0;
      for (auto i = static_cast<std::int32_t>(begin); i < end; ++i) {
        Load load{this->state_.force_n[i], ZeroSpin<Dim>()};
        if constexpr (Phys::kRotation) load.torque = this->state_.torque_nm[i];
        move2 = std::max(
            move2, VerletKickDrift<Dim, Phys::kRotation>(records_[i], opening_kick, dt, load));
      }
      chunk_move2[static_cast<std::size_t>(chunk)] = move2;
    };
    pool.ParallelFor(n, kick_drift);
    std::int64_t taken = steps;
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
      // One call per step, outside the particle loops.
      const bool stopping = step + 1 < steps && stop && stop();
      const bool last = step + 1 == steps || stopping;
      if (stopping) {
        this->pending_velocity_.resize(static_cast<std::size_t>(n));
        this->pending_spin_.resize(static_cast<std::size_t>(n));
        for (std::int32_t i = 0; i < n; ++i) {
          this->pending_velocity_[i] = records_[i].velocity_mass.v;
          this->pending_spin_[i] = records_[i].spin_inertia.w;
        }
      }
      std::fill(chunk_move2.begin(), chunk_move2.end(), 0.0);
      // Its own pass after the pair pass's barrier, not fused into the pair pass: closing each
      // particle inside its chunk as soon as its pairs were done (same sums, same bits) cost 4-10 %
      // more instructions and 3-12 % more cpu at 2000 spheres (docs/packing.md, "Figures behind
      // the engine's code").
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
      if (stopping) {
        taken = step + 1;
        break;
      }
    }
    StoreRecords();
    this->forces_valid_ = true;
    this->LeaveWorkingOrder();
    return taken;
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
      std::int64_t interacting = 0;
      if (!t.dense) {
        interacting = PairRangeCompacted(t, pair_begin, pair_end);
      } else if (t.single == nullptr) {
        // With single-precision contacts the dense blocks run in the chunk's float block and
        // the compacted ones convert into it (ContactBlock).
        interacting = PairRangeDense(t, pair_begin, pair_end);
      } else {
        interacting = PairRangeDense(*t.single, pair_begin, pair_end);
      }
      // Next step's choice for this chunk (its range hardly moves between steps).
      t.dense = static_cast<double>(interacting) >=
                this->settings_.dense_pair_fraction * static_cast<double>(pair_end - pair_begin);
      WallRange(t, begin * particle_count / items, end * particle_count / items);
    });
  }

  // The pair pass (engine_pair_pass.h). Declared inline like the members defined in the class,
  // so the compiler weighs inlining them the same way.
  // The dense pair pass is a template on the precision of its block (Real: double, or float for
  // single-precision contacts); the compacted one and the walls are double only.
  template <class Real>
  inline std::int64_t PairRangeDense(ContactScratch<Dim, Real>& t, std::int64_t begin,
                                     std::int64_t end);
  template <class Real>
  inline std::int64_t DenseBlockBaseline(ContactScratch<Dim, Real>& t, std::int64_t b, int n);
#if BOUNCECAL_SCENE_HAS_SIMD_PATHS
  template <class Real>
  [[gnu::target("avx2")]] inline std::int64_t DenseBlockAvx2(ContactScratch<Dim, Real>& t,
                                                             std::int64_t b, int n);
  template <class Real>
  [[BOUNCECAL_SCENE_AVX512]] inline std::int64_t DenseBlockAvx512(ContactScratch<Dim, Real>& t,
                                                                  std::int64_t b, int n);
  template <class Real>
  [[gnu::always_inline, gnu::target("avx2")]] inline int GatherTransposed(
      ContactScratch<Dim, Real>& t, std::int64_t b, int n) const;
  template <class Real>
  [[gnu::always_inline, gnu::target("avx2")]] inline void GatherFourTransposed(
      ContactScratch<Dim, Real>& t, int k, std::int64_t b, const std::int32_t* first,
      const std::int32_t* second, double cutoff_gap_m) const;
  template <class Real>
  [[gnu::always_inline, gnu::target("avx2")]] inline int ScatterTransposed(
      const ContactScratch<Dim, Real>& t, std::int64_t b, int n, std::int64_t& interacting);
#endif
  template <class Real>
  [[gnu::always_inline]] inline void DenseGather(ContactScratch<Dim, Real>& t, std::int64_t b,
                                                 int k, int n) const;
  template <class Real>
  [[gnu::always_inline]] inline std::int64_t DenseScatter(const ContactScratch<Dim, Real>& t,
                                                          std::int64_t b, int k, int n);
  inline std::int64_t PairRangeCompacted(Scratch& t, std::int64_t begin, std::int64_t end);
  inline void ContactBlock(int n, Scratch& t);
  inline void GatherBlock(int n, Scratch& t) const;
  inline void ScatterBlock(int n, const Scratch& t);

  // Particle-wall contacts (engine_walls.h).
  inline void WallRange(Scratch& t, std::int64_t begin, std::int64_t end);
  inline void WallBlock(int n, Scratch& t);
  [[gnu::always_inline]] inline void AddWallLoads(std::int32_t i, V& force, S& twist) const;

  // Sum of the pair forces of particle i in a fixed order, plus walls, gravity and damping;
  // stored, and returned for the integrator.
  [[gnu::always_inline]] Load GatherForce(std::int32_t i) {
    const auto& pairs = this->pairs_;
    const double r_i = records_[static_cast<std::size_t>(i)].position_radius.s;
    const V weight = records_[static_cast<std::size_t>(i)].velocity_mass.s * gravity_;
    // Gravity joins the sum first (the order every result so far was computed in) unless the
    // local damping must see the other forces alone; then it is added after the damping.
    const bool weight_after_damping = Phys::kLocalDamping && this->settings_.local_damping_scope ==
                                                                 LocalDampingScope::kContactForces;
    V force = weight_after_damping ? V::Zero() : weight;
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
    AddWallLoads(i, force, twist);
    S torque = -r_i * twist;
    if constexpr (Phys::kLocalDamping) {
      const Record& record = records_[static_cast<std::size_t>(i)];
      ApplyLocalDamping<Dim, Phys::kRotation>(this->settings_.local_damping, record.velocity_mass.v,
                                              record.spin_inertia.w, force, torque);
      if (weight_after_damping) force += weight;
    }
    return {force, torque};
  }

  ContactStages<Dim, Law, Phys> stages_;
  V gravity_;
  ContactSimd simd_;              // the build of the contact arithmetic (same results)
  std::vector<Scratch> scratch_;  // one per pool chunk
  // The dense blocks' scratch per pool chunk with single-precision contacts; empty otherwise.
  std::vector<ContactScratch<Dim, float>> single_scratch_;
  std::vector<Record> records_;  // see LoadRecords
  // Force on the particle and n x F_t of each (particle, wall) contact, particle * walls + wall;
  // written every step for the walls a particle is near (WallRange), zero when not touching.
  std::vector<PairResult> wall_result_;
};

}  // namespace bouncecal::dem::scene

// The members defined in their own files.
#include "engine/engine_pair_pass.h"
#include "engine/engine_walls.h"

namespace bouncecal::dem::scene {

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

// The force loops of every law take minutes to compile, so they are split over translation units
// by law: part P (engine_2d_part<P>.cc, engine_3d_part<P>.cc) builds the laws whose position in
// ContactLaw is P modulo kEngineParts, and the parts compile in parallel. A new law lands in a
// part by its position; no list names the laws.
inline constexpr std::size_t kEngineParts = 3;

template <int Dim, std::size_t Part>
std::unique_ptr<EngineBase<Dim>> MakeEnginePart(const EngineSettings& settings,
                                                std::vector<Wall<Dim>> walls, const ContactLaw& law,
                                                const PhysicsSpec& physics) {
  return std::visit(
      [&](const auto& typed_law) -> std::unique_ptr<EngineBase<Dim>> {
        using Law = std::decay_t<decltype(typed_law)>;
        if constexpr (static_cast<std::size_t>(kKindOf<Law>) % kEngineParts == Part) {
          return MakeEngineForLaw<Dim>(settings, std::move(walls), typed_law, physics);
        } else {
          return nullptr;  // another part's law: MakeEngine never asks this part for it
        }
      },
      law);
}

// Each part is compiled once, in its own file.
extern template std::unique_ptr<EngineBase<2>> MakeEnginePart<2, 0>(const EngineSettings&,
                                                                    std::vector<Wall<2>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
extern template std::unique_ptr<EngineBase<2>> MakeEnginePart<2, 1>(const EngineSettings&,
                                                                    std::vector<Wall<2>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
extern template std::unique_ptr<EngineBase<2>> MakeEnginePart<2, 2>(const EngineSettings&,
                                                                    std::vector<Wall<2>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
extern template std::unique_ptr<EngineBase<3>> MakeEnginePart<3, 0>(const EngineSettings&,
                                                                    std::vector<Wall<3>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
extern template std::unique_ptr<EngineBase<3>> MakeEnginePart<3, 1>(const EngineSettings&,
                                                                    std::vector<Wall<3>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
extern template std::unique_ptr<EngineBase<3>> MakeEnginePart<3, 2>(const EngineSettings&,
                                                                    std::vector<Wall<3>>,
                                                                    const ContactLaw&,
                                                                    const PhysicsSpec&);
static_assert(kEngineParts == 3, "declare and define (engine_*_part*.cc) each part");

template <int Dim>
std::unique_ptr<EngineBase<Dim>> MakeEngine(const EngineSettings& settings,
                                            std::vector<Wall<Dim>> walls,
                                            const ContactLawConfig& law,
                                            const PhysicsSpec& physics) {
  const auto evaluator = MakeContactLaw(law);
  switch (evaluator.index() % kEngineParts) {
    case 0:
      return MakeEnginePart<Dim, 0>(settings, std::move(walls), evaluator, physics);
    case 1:
      return MakeEnginePart<Dim, 1>(settings, std::move(walls), evaluator, physics);
    default:
      return MakeEnginePart<Dim, 2>(settings, std::move(walls), evaluator, physics);
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_ENGINE_IMPL_H_
