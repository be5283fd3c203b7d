#ifndef BOUNCECAL_DEM_PACKING_H_
#define BOUNCECAL_DEM_PACKING_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "bouncecal/dem/packing_measures.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::dem {

struct PackProgress {
  double time_s = 0;
  double duration_s = 0;
  std::int64_t steps = 0;
  std::int64_t particles = 0;
  double wall_s = 0;
  // Projected wall time still to go: this run's measured speed over the remaining steps at the
  // final particle count (WallTimeProjection, pack_projection.h).
  double remaining_wall_s = 0;
};

struct PackOptions {
  int threads = 1;  // the engine's own worker threads; results are identical for any count
  // Verlet skin as a fraction of the largest diameter: pairs are listed when their surfaces are
  // closer than this and the list is rebuilt once a particle has moved half of it.
  double skin_diameters = 0.1;
  // The skin adapts between this and skin_diameters: at each rebuild it is what the fastest
  // particle crosses (twice) in skin_rebuild_steps steps. Wide while particles fall, narrow once
  // they rest, where fewer listed pairs make each step cheaper. >= skin_diameters: fixed skin.
  double min_skin_diameters = 0.01;
  double skin_rebuild_steps = 50;
  // A time step beyond the stability limit of the scene's stiffest normal contact (see
  // PackSummary::time_step_limit_s) is refused unless this is set.
  bool allow_unstable_step = false;
  // The contact arithmetic of the particle pairs in float, at float's rounding in each contact
  // force; positions, velocities, force sums and wall contacts stay double.
  // Off: the default, bit for bit the double engine. Measured about 5 % faster than double on the
  // AVX-512 host; its speed and its effect on the observables: docs/packing.md, "Single
  // precision: the speed/accuracy trade".
  bool single_precision_contacts = false;
  bool brute_force_pairs = false;    // list all N^2/2 pairs (reference path for tests)
  std::optional<double> duration_s;  // overrides the scene's duration
  std::int64_t progress_every_steps = 2000;
  std::function<void(const PackProgress&)> progress;
  // Called once every set-up check has passed (and a resume checkpoint was accepted), before
  // the first snapshot or step: the point from which the run will write its outputs, so the
  // caller may clear an earlier run's only then.
  std::function<void()> started;
  // Called at t = 0, every outputs.snapshot_interval_s and at the end when that is > 0.
  std::function<void(const ParticleSnapshot&)> snapshot;
  // Simulated seconds between checkpoints; 0: none. A checkpoint is taken at the first boundary
  // between blocks of steps (history, snapshot, pour batch or progress_every_steps) at or after
  // each multiple, never inside a block: splitting a block would change the integrator's
  // arithmetic, and a run with checkpoints must give the bits of one without.
  double checkpoint_every_s = 0;
  // Receives each checkpoint: the bytes to store (atomically) and the simulated time they hold.
  std::function<void(const std::string& checkpoint, double time_s)> checkpoint;
  // Polled once per step (between its forces and its closing kick, on the calling thread, so it
  // must be cheap: the command line reads a flag its signal handler sets): true ends the run at
  // the end of that step, with a checkpoint (to `checkpoint`) and PackStopReason::kInterrupted.
  // A checkpoint taken inside a block keeps what the rest of the block needs to continue
  // bit-identically.
  std::function<bool()> stop_requested;
  // A checkpoint written by `checkpoint` to continue from, and its file name for messages. It
  // must come from the same scene and the same trajectory-steering options (skin,
  // progress_every_steps, ...; not threads); otherwise RunPacking throws InputError.
  std::optional<std::string> resume_checkpoint;
  std::string resume_name = "checkpoint";

  // Throws ConfigError naming the option and its valid range.
  void Validate() const;
};

enum class PackStopReason { kDuration, kUnstable, kInterrupted };
std::string_view ToString(PackStopReason reason);

struct HistoryPoint {
  double time_s = 0;
  double packing_density = 0;  // in the scene's band (3D) or window (2D)
  double kinetic_energy_j = 0;
  double max_speed_mps = 0;
  std::int64_t particles = 0;
};

struct PackSummary {
  PackStopReason stop_reason = PackStopReason::kDuration;
  std::string message;  // one human sentence
  std::string physics;  // the force loop that ran, e.g. "walton-braun+tangential+rotation"
  std::int64_t particles = 0;
  std::int64_t particles_not_inserted = 0;  // pour/random regions too full to take them all
  std::int64_t steps = 0;
  std::int64_t neighbor_rebuilds = 0;
  double time_step_s = 0;
  // omega dt < 2 for the stiffest single normal contact of the scene's particles (a longer
  // step is refused); a pack usually needs a step well below it (several contacts load a
  // particle at once). The tangential spring's limit only warns: beyond it sticking contacts
  // chatter until they slide, and friction bounds them. Infinite without tangential physics.
  double time_step_limit_s = 0;
  double tangential_time_step_limit_s = 0;
  std::vector<std::string> warnings;  // one sentence each: the run went on, but read these
  // Choices the scene made knowingly and explains (time_step_reason): one sentence each.
  std::vector<std::string> notes;
  double simulated_s = 0;
  double wall_s = 0;  // of this call
  // wall_s plus the wall time recorded in the resumed checkpoint: the runs that led to this
  // state (up to the checkpoint each one was resumed from). Equals wall_s when not resumed.
  double total_wall_s = 0;
  double particle_steps_per_s = 0;
  int threads = 1;
  // The contacts' arithmetic, PackOptions::single_precision_contacts: a single-precision run is
  // not double's trajectory, so its summary must say which it is.
  bool single_precision_contacts = false;
  double packing_density = 0;
  double packing_density_by_count = 0;  // CentreCountDensity: paper 004's estimator
  double kinetic_energy_j = 0;
  CoordinationStats coordination;
  DensityProfile profile;
  std::vector<HistoryPoint> history;
  ParticleSnapshot final_state;
  // FNV-1a over the bits of every final position, velocity and spin: equal digests mean
  // bit-identical final states (thread counts, a resumed run against an uninterrupted one).
  std::uint64_t state_digest = 0;
  // Ran to its duration but never came to rest: its kinetic energy stopped falling while still
  // above 1 % of its peak (see the not-at-rest warning). The measures describe a boiling state,
  // not a packing; the CLI exits with status 3 (time_step_s too coarse).
  bool boiling = false;
};

// Runs a packing scene to its duration. Throws ConfigError/InputError for a bad scene (region
// too small, unreadable particle file); an unstable run (non-finite state) stops early with
// kUnstable and a message instead.
PackSummary RunPacking(const Scene& scene, const PackOptions& options = {});

// "walton-braun+tangential+rotation+vdw+local-damping": the physics a scene runs with.
std::string DescribePhysics(const Scene& scene);

// One LAMMPS text dump frame (ITEM: TIMESTEP ... ITEM: ATOMS id type radius x y z vx vy vz),
// readable by OVITO and ParaView.
void WriteLammpsDump(std::ostream& out, const ParticleSnapshot& snapshot, const Scene& scene);

// A LAMMPS data file (atom_style sphere) of the snapshot, to feed the same start to LAMMPS.
void WriteLammpsData(std::ostream& out, const ParticleSnapshot& snapshot, const Scene& scene);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_PACKING_H_
