#ifndef BOUNCECAL_DEM_ENGINE_ENGINE_H_
#define BOUNCECAL_DEM_ENGINE_ENGINE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/worker_pool.h"
#include "engine/walls.h"
#include "scene/pair_list.h"
#include "scene/vec.h"

namespace bouncecal::dem::scene {

class ByteReader;  // checkpoint_bytes.h
class ByteWriter;

// The instruction sets the contact arithmetic is compiled for, narrowest first. kAvx512 needs
// AVX-512 F, DQ and VL and runs 8 contacts per instruction.
enum class ContactSimd { kBaseline, kAvx2, kAvx512 };

// Everything the force loop needs besides the law and the physics flags, in SI.
struct EngineSettings {
  double time_step_s = 1e-5;
  double gravity_mps2 = 9.81;  // acts along -z (3D) or -y (2D)
  double tangential_stiffness_n_per_m = 1e7;
  double friction = 0.3;
  double wall_friction = 0.3;
  double hamaker_j = 21.1e-20;
  double vdw_min_gap_m = 4e-10;
  double vdw_cutoff_gap_m = 1e-6;
  double local_damping = 0.7;
  LocalDampingScope local_damping_scope = LocalDampingScope::kUnbalancedForce;
  // Paper 004 (sections 2 and 3.1): a particle's velocity is set to zero at its first collision
  // (with a particle or a wall), once per particle. See first_contact_stop.cc.
  bool stop_at_first_contact = false;
  // Verlet skin: pairs closer than r_i + r_j + skin are listed and the list is rebuilt once any
  // particle has moved skin/2. 0 rebuilds every step.
  double skin_m = 0;
  // When in [0, skin_m), the skin is chosen again at each rebuild, between this and skin_m: wide
  // enough that the fastest particle at that moment needs skin_rebuild_steps steps to cross
  // half of it. A pour needs the wide skin (fast particles, frequent rebuilds); a settled pack
  // hardly moves, and every listed pair that does not touch costs a distance test per step, so
  // there the narrow one is cheaper. The rebuild rule above stays exact either way: the choice
  // only moves cost between rebuilds and steps, and the order of the force sums.
  double min_skin_m = -1;
  double skin_rebuild_steps = 50;
  // A chunk of the pair list runs every listed pair through the contact arithmetic (no
  // compaction) once at least this fraction of its pairs interacted in the previous step, and
  // only the interacting ones otherwise. Speed only: results are the same bit for bit. 0 always
  // runs all listed pairs, > 1 always compacts (tests compare the two). 0.5 was the fastest of
  // the values tried on the paper 000 pour (docs/packing.md, "Figures behind the engine's code").
  double dense_pair_fraction = 0.5;
  bool brute_force_pairs = false;  // list every pair i < j (tests only: O(N^2))
  // Reorder the particles by grid cell at each rebuild (inside the engine only: state() keeps
  // the order they were added in), so that neighbours are close in memory and each thread's
  // range is a compact region. Changes the order of force sums, hence the last bits.
  bool sort_by_cell = true;
  // The widest build of the contact arithmetic the engine may run; it runs the widest one this
  // CPU has up to this. The results are the same bit for bit (tests compare the builds).
  ContactSimd max_contact_simd = ContactSimd::kAvx512;
  // The contact arithmetic of the particle pairs in float instead of double: not the same bits,
  // each contact force carries float's rounding, and it was measured only about 5 % faster (0-10 %)
  // (docs/packing.md, "Single precision: the speed/accuracy trade"). Positions, velocities, springs
  // between steps, force sums and wall contacts stay double; the results are still the same for any
  // thread count. Off by default.
  bool single_precision_contacts = false;
  int threads = 1;
};

// Spheres in 3D; in 2D the particles are spheres whose centres move in a plane (paper 004 packs
// spheres in a monolayer), so mass is that of a sphere in both cases.
inline double SphereMassKg(double density_kg_per_m3, double radius_m) {
  constexpr double kPi = 3.14159265358979323846;
  return density_kg_per_m3 * 4.0 / 3.0 * kPi * radius_m * radius_m * radius_m;
}

template <int Dim>
struct ParticleState {
  std::vector<Vec<Dim>> position_m;
  std::vector<Vec<Dim>> velocity_mps;
  std::vector<Vec<Dim>> force_n;
  std::vector<Spin<Dim>> angular_velocity_radps;
  std::vector<Spin<Dim>> torque_nm;
  std::vector<double> radius_m;
  std::vector<double> mass_kg;
  std::vector<double> inverse_mass;
  std::vector<double> inverse_inertia;  // solid sphere: I = 2/5 m r^2 (2D disks too: see docs)
  std::vector<std::int32_t> species;

  std::int32_t size() const { return static_cast<std::int32_t>(position_m.size()); }
};

// The physics a force loop is compiled for. Only what a scene declares runs in its inner loop.
template <bool Tangential, bool Rotation, bool VanDerWaals, bool LocalDamping>
struct Physics {
  static constexpr bool kTangential = Tangential;
  static constexpr bool kRotation = Rotation;
  static constexpr bool kVanDerWaals = VanDerWaals;
  static constexpr bool kLocalDamping = LocalDamping;
};

// State, walls, neighbour list and contact history; the force loop lives in the derived
// template so that the law and the physics are compile-time choices.
template <int Dim>
class EngineBase {
 public:
  EngineBase(const EngineSettings& settings, std::vector<Wall<Dim>> walls);
  virtual ~EngineBase() = default;
  EngineBase(const EngineBase&) = delete;
  EngineBase& operator=(const EngineBase&) = delete;

  // Appends particles at rest (or with the given velocity); forces are recomputed lazily.
  void AddParticle(const Vec<Dim>& position_m, const Vec<Dim>& velocity_mps, double radius_m,
                   double density_kg_per_m3, std::int32_t species);

  // Forces and torques at the current positions and velocities (no integration). Outside
  // these two calls state() is in the order the particles were added.
  virtual void ComputeForces() = 0;
  // `steps` velocity-Verlet steps; positions, velocities and forces are synchronised after it.
  void Advance(std::int64_t steps) { AdvanceUntil(steps, nullptr); }
  // The same, but `stop` (when set) is asked once per step, on the calling thread, after the
  // step's forces: true makes that step the last one, so a stop request is met within one step
  // (packing.cc: SIGINT/SIGTERM on a large scene) instead of at the end of the block. Returns
  // the steps taken. Ending a block early splits the fused kick of velocity Verlet into two
  // halves, which rounds differently: the velocities before the closing half kick are kept
  // (pending_velocity_), and the next Advance takes the whole kick from them, so that a run
  // stopped and continued (also through SaveCheckpoint / RestoreCheckpoint) ends in the bits of
  // one that was not.
  virtual std::int64_t AdvanceUntil(std::int64_t steps, const std::function<bool()>& stop) = 0;

  const ParticleState<Dim>& state() const { return state_; }
  // Changing the state after a stopped Advance gives up the pending whole kick: the next step
  // starts from the velocities set here (two half kicks, correct but not the same bits).
  ParticleState<Dim>& mutable_state() {
    DropPendingKick();
    return state_;
  }
  const EngineSettings& settings() const { return settings_; }
  const std::vector<Wall<Dim>>& walls() const { return walls_; }
  // The pair list and spring of pair p, in the engine's internal particle order (tests).
  const PairList& pairs() const { return pairs_; }
  std::int64_t steps() const { return steps_; }
  double time_s() const { return static_cast<double>(steps_) * settings_.time_step_s; }
  std::int64_t rebuilds() const { return rebuilds_; }
  // The Verlet skin of the current pair list.
  double skin_m() const { return skin_m_; }
  // Translational plus rotational kinetic energy.
  double KineticEnergyJ() const;
  // True once a position or velocity is not finite (the step was unstable).
  bool HasNonFiniteState() const;
  const Vec<Dim>& PairShear(std::size_t p) const { return pair_shear_[p]; }
  // Particles that have not collided yet; only tracked with settings().stop_at_first_contact
  // (otherwise every particle counts as untouched).
  std::int64_t untouched() const { return untouched_; }

  // Every member the next Advance reads, as it is (engine_checkpoint.cc): restored into an
  // engine made with the same settings, walls, law and physics, the run goes on bit for bit as
  // if it had never stopped. Call between Advance calls. Restore throws InputError (through
  // `in`) when the arrays do not fit together, and leaves the engine unusable then.
  void SaveCheckpoint(ByteWriter& out) const;
  void RestoreCheckpoint(ByteReader& in);

 protected:
  // New pair list (grid or all pairs), carrying over the history of pairs that stay listed.
  void RebuildPairs(bool van_der_waals);
  void UpdateWallNeighbours();
  // The force loop runs on the particles in the internal order (order_); state_ is in the
  // order they were added whenever the caller can see it. Both are idempotent.
  void EnterWorkingOrder();
  void LeaveWorkingOrder();
  // Moves the particle at internal index from[k] to k (state, wall history, order_).
  void PermuteParticles(const std::vector<std::int32_t>& from);
  double PairReachM(bool van_der_waals) const;
  // The skin for the next list (see EngineSettings::min_skin_m), from the current velocities.
  double ChooseSkinM() const;
  Vec<Dim> Gravity() const;
  void DropPendingKick() {
    pending_velocity_.clear();
    pending_spin_.clear();
  }
  bool kick_pending() const { return !pending_velocity_.empty(); }
  // With stop_at_first_contact: zeroes the velocity and spin of every particle that overlaps a
  // particle or wall for the first time. Call in the working order with a valid pair list,
  // after the drift and before the forces (first_contact_stop.cc).
  void StopFirstContacts();

  // Per listed pair, written every step: the force on the first particle and n x F_t (the
  // torque on a member is -radius * twist). One record so the gather touches one cache line.
  struct PairResult {
    Vec<Dim> force_n;
    Spin<Dim> twist_n;
  };

  EngineSettings settings_;
  std::vector<Wall<Dim>> walls_;
  ParticleState<Dim> state_;
  PairList pairs_;
  std::vector<Vec<Dim>> pair_shear_;
  std::vector<NormalHistory> pair_normal_history_;
  std::vector<PairResult> pair_result_;
  // 0 guarantees that pair p's result, spring and normal history are all zero (it did not
  // interact last step), so the distance pass need not clear or even read them; every rebuild
  // sets it to 1 (unknown).
  std::vector<std::uint8_t> pair_live_;
  std::vector<Vec<Dim>> wall_shear_;  // particle * walls + wall
  std::vector<NormalHistory> wall_normal_history_;
  // Bit w set: particle i was within the skin of wall w at the last rebuild, so it may touch it
  // before the next one. The others are skipped (their history is zero).
  std::vector<std::uint64_t> wall_near_;
  std::vector<Vec<Dim>> position_at_rebuild_;
  std::vector<std::int32_t> order_;  // internal index -> index in the order of AddParticle
  bool working_order_ = false;
  // Set by an Advance that a stop request ended inside its block: every particle's velocity and
  // spin before that step's closing half kick, in the internal order (see AdvanceUntil). Empty
  // otherwise.
  std::vector<Vec<Dim>> pending_velocity_;
  std::vector<Spin<Dim>> pending_spin_;
  std::unique_ptr<WorkerPool> pool_;
  double skin_m_ = 0;  // of the current pair list
  bool pairs_valid_ = false;
  bool forces_valid_ = false;
  std::int64_t steps_ = 0;
  std::int64_t rebuilds_ = 0;
  // Paper 004's first-contact stop: per particle in the order of AddParticle, whether it has
  // collided (only updated when settings_.stop_at_first_contact is on), and how many have not.
  std::vector<std::uint8_t> touched_;
  std::int64_t untouched_ = 0;
};

// The widest build of the contact arithmetic this CPU (and OS) can run and this library has.
ContactSimd CpuContactSimd();

// The engine for a scene: the law variant and physics flags become template arguments here.
template <int Dim>
std::unique_ptr<EngineBase<Dim>> MakeEngine(const EngineSettings& settings,
                                            std::vector<Wall<Dim>> walls,
                                            const ContactLawConfig& law,
                                            const PhysicsSpec& physics);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_ENGINE_H_
