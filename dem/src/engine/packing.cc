#include "bouncecal/dem/packing.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/dem/pack_projection.h"
#include "bouncecal/error.h"
#include "engine/checkpoint_bytes.h"
#include "engine/contact_limits.h"
#include "engine/energy_budget.h"
#include "engine/engine.h"
#include "engine/pack_checkpoint_file.h"
#include "engine/rest_checks.h"
#include "scene/insertion.h"
#include "scene/particle_file.h"

namespace bouncecal::dem {

void PackOptions::Validate() const {
  if (threads < 1 || threads > 1024) {
    throw ConfigError(fmt::format("threads = {} is outside [1, 1024]", threads));
  }
  if (!(skin_diameters >= 0 && skin_diameters <= 10)) {
    throw ConfigError(fmt::format("skin_diameters = {} is outside [0, 10]", skin_diameters));
  }
  if (!(min_skin_diameters >= 0 && min_skin_diameters <= 10)) {
    throw ConfigError(
        fmt::format("min_skin_diameters = {} is outside [0, 10]", min_skin_diameters));
  }
  if (!(skin_rebuild_steps >= 1 && skin_rebuild_steps <= 1e9)) {
    throw ConfigError(
        fmt::format("skin_rebuild_steps = {} is outside [1, 1e9]", skin_rebuild_steps));
  }
  if (duration_s && !(*duration_s >= 0 && std::isfinite(*duration_s))) {
    throw ConfigError(fmt::format("duration = {} s must be finite and >= 0", *duration_s));
  }
  if (progress_every_steps < 1) {
    throw ConfigError("progress_every_steps must be >= 1");
  }
  if (!(checkpoint_every_s >= 0 && std::isfinite(checkpoint_every_s))) {
    throw ConfigError(
        fmt::format("checkpoint_every_s = {} s must be finite and >= 0", checkpoint_every_s));
  }
}

std::string_view ToString(PackStopReason reason) {
  switch (reason) {
    case PackStopReason::kDuration:
      return "duration";
    case PackStopReason::kUnstable:
      return "unstable";
    case PackStopReason::kInterrupted:
      return "interrupted";
  }
  return "unknown";
}

std::string DescribePhysics(const Scene& scene) {
  std::string text(ToString(scene.material.law.kind));
  if (scene.physics.tangential) text += "+tangential";
  if (scene.physics.rotation) text += "+rotation";
  if (scene.physics.van_der_waals) text += "+vdw";
  if (scene.physics.local_damping) {
    // The default scope keeps its old name, so existing summaries stay byte-identical.
    text += scene.material.local_damping_scope == LocalDampingScope::kContactForces
                ? "+local-damping-contact-forces"
                : "+local-damping";
  }
  if (scene.physics.stop_at_first_contact) text += "+first-contact-stop";
  return text;
}

namespace {

template <int Dim>
ParticleSnapshot Snapshot(const scene::EngineBase<Dim>& engine) {
  const auto& s = engine.state();
  ParticleSnapshot snap;
  snap.dimension = Dim;
  snap.time_s = engine.time_s();
  snap.step = engine.steps();
  const auto n = static_cast<std::size_t>(s.size());
  snap.position_m.assign(n, Vec3{0, 0, 0});
  snap.velocity_mps.assign(n, Vec3{0, 0, 0});
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) {
      snap.position_m[i][d] = s.position_m[i][d];
      snap.velocity_mps[i][d] = s.velocity_mps[i][d];
    }
  }
  snap.radius_m = s.radius_m;
  snap.species = s.species;
  return snap;
}

template <int Dim>
std::vector<scene::NewParticle> Existing(const scene::EngineBase<Dim>& engine) {
  const auto& s = engine.state();
  std::vector<scene::NewParticle> out(static_cast<std::size_t>(s.size()));
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (int d = 0; d < Dim; ++d) out[i].position_m[d] = s.position_m[i][d];
    out[i].radius_m = s.radius_m[i];
  }
  return out;
}

template <int Dim>
void Insert(scene::EngineBase<Dim>& engine, const Scene& scene,
            const std::vector<scene::NewParticle>& particles) {
  scene::Vec<Dim> v;
  for (int d = 0; d < Dim; ++d) v[d] = scene.insertion.initial_velocity_mps[d];
  for (const auto& p : particles) {
    if (p.species >= static_cast<std::int32_t>(scene.particles.species.size())) {
      throw InputError(fmt::format(
          "{}: names species {} but the scene {} defines {} (species are 0-based); fix the "
          "particle file or add species",
          scene.insertion.file.string(), p.species, scene.source.string(),
          scene.particles.species.size()));
    }
    scene::Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = p.position_m[d];
    engine.AddParticle(
        x, v, p.radius_m,
        scene.particles.species[static_cast<std::size_t>(p.species)].density_kg_per_m3, p.species);
  }
}

HistoryPoint Sample(const ParticleSnapshot& snap, const Scene& scene, double kinetic_energy_j) {
  HistoryPoint point;
  point.time_s = snap.time_s;
  point.packing_density = PackingDensity(snap, scene);
  point.kinetic_energy_j = kinetic_energy_j;
  point.particles = static_cast<std::int64_t>(snap.size());
  for (const auto& v : snap.velocity_mps) {
    point.max_speed_mps =
        std::max(point.max_speed_mps, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  return point;
}

// The lightest particle, the largest one and the highest top, over the inserted particles and
// those still to be poured (which enter at the top of the pour region).
template <int Dim>
scene::BodyExtremes Extremes(const scene::EngineBase<Dim>& engine, const Scene& scene,
                             const std::vector<scene::NewParticle>& pending) {
  const int up = Dim - 1;
  const double floor = ContainerFloorM(scene);
  scene::BodyExtremes out;
  out.lightest_mass_kg = std::numeric_limits<double>::infinity();
  auto add = [&](double radius_m, double mass_kg, double top_m) {
    if (mass_kg < out.lightest_mass_kg) {
      out.lightest_mass_kg = mass_kg;
      out.lightest_radius_m = radius_m;
    }
    if (radius_m > out.largest_radius_m) {
      out.largest_radius_m = radius_m;
      out.largest_mass_kg = mass_kg;
    }
    out.highest_top_m = std::max(out.highest_top_m, top_m - floor);
  };
  const auto& s = engine.state();
  for (std::int32_t i = 0; i < s.size(); ++i) {
    add(s.radius_m[i], s.mass_kg[i], s.position_m[i][up] + s.radius_m[i]);
  }
  const auto& region = scene.insertion.region;
  const double region_top =
      region.kind == RegionKind::kCylinder ? region.z_max_m : region.max_m[up];
  for (const auto& p : pending) {
    const double density =
        scene.particles.species[static_cast<std::size_t>(p.species)].density_kg_per_m3;
    add(p.radius_m, scene::SphereMassKg(density, p.radius_m), region_top + p.radius_m);
  }
  return out;
}

template <int Dim>
double SmallestRadiusM(const scene::EngineBase<Dim>& engine,
                       const std::vector<scene::NewParticle>& pending) {
  double smallest = std::numeric_limits<double>::infinity();
  for (double r : engine.state().radius_m) smallest = std::min(smallest, r);
  for (const auto& p : pending) smallest = std::min(smallest, p.radius_m);
  return smallest;
}

template <int Dim>
double MaxSpeedMps(const scene::ParticleState<Dim>& state) {
  double speed = 0;
  for (const auto& v : state.velocity_mps) {
    // hypot: a runaway's 1e200 m/s must not square to inf and be reported as such.
    speed = std::max(speed, Dim == 3 ? std::hypot(v[0], v[1], v[Dim - 1]) : std::hypot(v[0], v[1]));
  }
  return speed;
}

// Kinetic energy beyond this multiple of the energy the particles brought in stops a run as
// unstable. Not 1: velocity Verlet's own error at a coarse (paper) step adds some, and the
// budget's van der Waals term is an estimate.
constexpr double kEnergyBudgetFactor = 2;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::int64_t StepsFor(double interval_s, double dt) {
  if (!(interval_s > 0)) return std::numeric_limits<std::int64_t>::max();
  return std::max<std::int64_t>(1, std::llround(interval_s / dt));
}

// Pending particles field by field: NewParticle has padding, whose bytes are not defined, and a
// checkpoint of one state must be one file.
void PutParticles(scene::ByteWriter& out, const std::vector<scene::NewParticle>& particles) {
  std::vector<Vec3> position;
  std::vector<double> radius;
  std::vector<std::int32_t> species;
  for (const auto& p : particles) {
    position.push_back(p.position_m);
    radius.push_back(p.radius_m);
    species.push_back(p.species);
  }
  out.PutVector(position);
  out.PutVector(radius);
  out.PutVector(species);
}

std::vector<scene::NewParticle> GetParticles(scene::ByteReader& in) {
  const auto position = in.GetVector<Vec3>();
  const auto radius = in.GetVector<double>();
  const auto species = in.GetVector<std::int32_t>();
  if (radius.size() != position.size() || species.size() != position.size()) {
    in.Fail("its particles still to pour do not fit together");
  }
  std::vector<scene::NewParticle> particles(position.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    particles[i] = {position[i], radius[i], species[i]};
  }
  return particles;
}

// What decides the trajectory from here on: the engine's settings (not the thread count, which
// does not change it), law, physics and walls, the start state and the particles still to come,
// the random stream and the block lengths (see PackOptions::checkpoint_every_s). A checkpoint
// resumes only into a set-up with the same fingerprint.
template <int Dim>
std::uint64_t SetupFingerprint(const Scene& scene, const scene::EngineSettings& settings,
                               const scene::EngineBase<Dim>& engine,
                               const std::vector<scene::NewParticle>& pending,
                               const scene::SceneRandom& random,
                               const std::vector<std::int64_t>& block_lengths) {
  scene::ByteWriter out;
  out.Put(Dim);
  for (const double value :
       {settings.time_step_s, settings.gravity_mps2, settings.tangential_stiffness_n_per_m,
        settings.friction, settings.wall_friction, settings.hamaker_j, settings.vdw_min_gap_m,
        settings.vdw_cutoff_gap_m, settings.local_damping, settings.skin_m, settings.min_skin_m,
        settings.skin_rebuild_steps}) {
    out.Put(value);
  }
  for (const bool flag :
       {settings.stop_at_first_contact, settings.brute_force_pairs, settings.sort_by_cell}) {
    out.Put(static_cast<std::uint8_t>(flag));
  }
  out.PutString(DescribePhysics(scene));
  // Only when on, so that a double run's fingerprint (and its checkpoints) stay as they were.
  if (settings.single_precision_contacts) out.PutString("single-precision contacts");
  for (const auto& [name, value] : scene.material.law.parameters) {
    out.PutString(name);
    out.Put(value);
  }
  const auto& c = scene.container;
  out.Put(static_cast<std::int32_t>(c.kind));
  for (const Vec3& v : {c.center_m, c.min_m, c.max_m, c.point_m, c.normal}) out.Put(v);
  out.Put(c.radius_m);
  out.Put(c.height_m);
  out.Put(static_cast<std::uint8_t>(c.closed_top));
  const auto& st = engine.state();
  out.PutVector(st.position_m);
  out.PutVector(st.velocity_mps);
  out.PutVector(st.radius_m);
  out.PutVector(st.mass_kg);
  out.PutVector(st.species);
  PutParticles(out, pending);
  out.Put(random.state());
  out.PutVector(block_lengths);
  return scene::Fnv1a(out.bytes());
}

// FNV-1a over the bytes of every particle's position, velocity and spin, in insertion order:
// equal digests mean bit-identical final states.
template <int Dim>
std::uint64_t StateDigest(const scene::ParticleState<Dim>& state) {
  scene::ByteWriter out;
  out.PutVector(state.position_m);
  out.PutVector(state.velocity_mps);
  out.PutVector(state.angular_velocity_radps);
  return scene::Fnv1a(out.bytes());
}

// The cadences of a run, in steps; `never` where a thing does not happen.
struct StepCadence {
  static constexpr std::int64_t never = std::numeric_limits<std::int64_t>::max();
  std::int64_t total = 0;
  std::int64_t history = never;
  std::int64_t snapshot = never;
  std::int64_t batch = never;
  std::int64_t progress = never;
  std::int64_t checkpoint = never;
};

std::int64_t NextMultiple(std::int64_t step, std::int64_t every) {
  if (every == StepCadence::never) return every;
  return (step / every + 1) * every;
}

void CheckProfileBins(const Scene& scene) {
  const double container_height_m = ContainerTopM(scene) - ContainerFloorM(scene);
  if (scene.measurement.profile_bin_m > 0 && std::isfinite(container_height_m) &&
      container_height_m / scene.measurement.profile_bin_m > kMaxProfileBins) {
    throw ConfigError(fmt::format(
        "{}: measurement.profile_bin_m = {:.3g} m cuts the {:.3g} m tall container into more "
        "than {:.0f} bins; use a larger bin",
        scene.source.string(), scene.measurement.profile_bin_m, container_height_m,
        kMaxProfileBins));
  }
}

scene::EngineSettings EngineSettingsFor(const Scene& scene, const PackOptions& options) {
  const auto& m = scene.material;
  scene::EngineSettings settings;
  settings.time_step_s = scene.time_step_s;
  settings.gravity_mps2 = scene.gravity_mps2;
  settings.tangential_stiffness_n_per_m = m.tangential_stiffness_n_per_m;
  settings.friction = m.friction;
  settings.wall_friction = m.wall_friction;
  settings.hamaker_j = m.hamaker_j;
  settings.vdw_min_gap_m = m.vdw_min_gap_m;
  settings.vdw_cutoff_gap_m = m.vdw_cutoff_gap_m;
  settings.local_damping = m.local_damping;
  settings.local_damping_scope = m.local_damping_scope;
  settings.stop_at_first_contact = scene.physics.stop_at_first_contact;
  settings.skin_m = options.skin_diameters * scene.particles.diameter.MaxDiameterM();
  settings.min_skin_m = options.min_skin_diameters * scene.particles.diameter.MaxDiameterM();
  settings.skin_rebuild_steps = options.skin_rebuild_steps;
  settings.brute_force_pairs = options.brute_force_pairs;
  settings.single_precision_contacts = options.single_precision_contacts;
  settings.threads = options.threads;
  return settings;
}

// One packing run: the engine and what the stepping carries from block to block (the particles
// still to pour, the random stream that places them, the energy budget, the summary so far).
// The set-up's checks run in the constructor, in the order a user meets them: the measurement,
// the start, van der Waals overlaps, the time step.
template <int Dim>
class PackingRun {
 public:
  PackingRun(const Scene& scene, const PackOptions& options);
  PackSummary Run() &&;

 private:
  void PlaceStart();
  void ScheduleSteps();
  std::uint64_t Fingerprint() const;
  void Resume();
  void SaveCheckpoint() const;
  std::optional<std::string> Instability() const;
  void PourBatch();
  void Record(std::int64_t step);
  void Measure();

  const Scene& scene_;
  const PackOptions& options_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  const double dt_;
  const double duration_s_;
  scene::EngineSettings settings_;
  std::unique_ptr<scene::EngineBase<Dim>> engine_;
  scene::SceneRandom random_;
  std::vector<scene::NewParticle> pending_;
  PackSummary summary_;
  scene::TimeStepLimits limits_;
  std::optional<scene::EnergyBudget> budget_;
  // A particle that moves half its radius in one step overlaps whatever it meets by that much
  // before any force acts: no contact is resolved any more, energy is created, particles pass
  // through walls. Stop there rather than run on to absurd (finite) numbers.
  double runaway_speed_mps_ = 0;
  StepCadence cadence_;
  std::uint64_t fingerprint_ = 0;
  double earlier_wall_s_ = 0;  // of the runs before the checkpoint this one resumes
};

template <int Dim>
PackingRun<Dim>::PackingRun(const Scene& scene, const PackOptions& options)
    : scene_(scene),
      options_(options),
      dt_(scene.time_step_s),
      duration_s_(options.duration_s.value_or(scene.duration_s)),
      random_(scene.insertion.seed) {
  CheckProfileBins(scene_);
  settings_ = EngineSettingsFor(scene_, options_);
  engine_ = scene::MakeEngine<Dim>(settings_, scene::ContainerWalls<Dim>(scene_.container),
                                   scene_.material.law, scene_.physics);
  PlaceStart();
  const scene::BodyExtremes bodies = Extremes(*engine_, scene_, pending_);
  if (const auto problem = scene::VanDerWaalsOverlapProblem(scene_, bodies)) {
    throw ConfigError(scene_.source.string() + ": " + *problem);
  }
  limits_ = scene::CheckTimeStep(scene_, bodies, options_.allow_unstable_step, summary_.warnings,
                                 summary_.notes);
  if (options_.single_precision_contacts) {
    // Named as both front ends name the option (`pack --precision single`, bouncecal.pack's
    // precision="single"), not as the struct's bool.
    summary_.notes.push_back(
        "the particle-particle contacts were computed in single precision (`precision=single`): "
        "not the double engine's bits (docs/packing.md, 'Single precision: the speed/accuracy "
        "trade')");
  }
  budget_.emplace(scene_, *engine_,
                  engine_->state().size() + static_cast<std::int64_t>(pending_.size()));
  runaway_speed_mps_ = 0.5 * SmallestRadiusM(*engine_, pending_) / dt_;
  ScheduleSteps();
  summary_.physics = DescribePhysics(scene_);
  summary_.time_step_s = dt_;
  summary_.time_step_limit_s = limits_.normal.limit_s;
  summary_.tangential_time_step_limit_s = limits_.tangential.limit_s;
  summary_.threads = options_.threads;
  summary_.single_precision_contacts = options_.single_precision_contacts;
  summary_.history.push_back(Sample(Snapshot(*engine_), scene_, engine_->KineticEnergyJ()));
  fingerprint_ = Fingerprint();
}

// A file's particles, or as many drawn particles as the region holds now; the rest wait in
// `pending_` for the pour's batches.
template <int Dim>
void PackingRun<Dim>::PlaceStart() {
  if (scene_.insertion.kind == InsertionKind::kFile) {
    std::vector<scene::NewParticle> start;
    if (scene_.insertion.start_particles.empty()) {
      start = scene::ReadParticleFile(scene_.insertion.file, Dim);
    } else {
      for (const auto& p : scene_.insertion.start_particles) {
        start.push_back({p.position_m, p.radius_m, p.species});
      }
    }
    Insert(*engine_, scene_, start);
    return;
  }
  pending_ = scene::DrawParticles(scene_, random_);
  const auto placed = scene::PlaceInRegion(scene_, pending_, {}, random_);
  if (scene_.insertion.kind == InsertionKind::kRandom && placed.size() < pending_.size()) {
    throw ConfigError(fmt::format(
        "{}: insertion.region holds only {} of the {} particles without overlap after {} "
        "attempts; enlarge the region or raise insertion.max_attempts",
        scene_.source.string(), placed.size(), pending_.size(), scene_.insertion.max_attempts));
  }
  Insert(*engine_, scene_, placed);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(placed.size()));
}

template <int Dim>
void PackingRun<Dim>::ScheduleSteps() {
  cadence_.total = std::llround(duration_s_ / dt_);
  cadence_.history = StepsFor(scene_.measurement.history_interval_s, dt_);
  cadence_.snapshot = StepsFor(scene_.outputs.snapshot_interval_s, dt_);
  if (scene_.insertion.kind == InsertionKind::kPour) {
    cadence_.batch = StepsFor(scene_.insertion.batch_interval_s, dt_);
  }
  cadence_.progress = options_.progress_every_steps;
  if (options_.checkpoint) cadence_.checkpoint = StepsFor(options_.checkpoint_every_s, dt_);
}

template <int Dim>
std::uint64_t PackingRun<Dim>::Fingerprint() const {
  return SetupFingerprint(scene_, settings_, *engine_, pending_, random_,
                          {cadence_.history, cadence_.snapshot, cadence_.batch, cadence_.progress});
}

template <int Dim>
void PackingRun<Dim>::SaveCheckpoint() const {
  if (!options_.checkpoint) return;
  scene::ByteWriter payload;
  engine_->SaveCheckpoint(payload);
  payload.Put(random_.state());
  payload.Put(budget_->joules());
  PutParticles(payload, pending_);
  payload.PutVector(summary_.history);
  // The wall time of the runs that led to this state, so that a resumed run reports the total.
  payload.Put(earlier_wall_s_ + SecondsSince(start_));
  scene::PackCheckpointFrame frame;
  frame.dimension = Dim;
  frame.fingerprint = fingerprint_;
  frame.step = engine_->steps();
  frame.time_s = engine_->time_s();
  frame.payload = payload.bytes();
  options_.checkpoint(scene::WritePackCheckpointFrame(frame), engine_->time_s());
}

template <int Dim>
void PackingRun<Dim>::Resume() {
  const std::string& name = options_.resume_name;
  const auto frame = scene::ReadPackCheckpointFrame(*options_.resume_checkpoint, name);
  if (frame.dimension != Dim || frame.fingerprint != fingerprint_) {
    throw InputError(fmt::format(
        "{}: was written for another scene or other options (its set-up fingerprint {:016x} "
        "is not this run's {:016x}: scene file, material, seed, start file, "
        "`skin_diameters`, `min_skin_diameters`); resume with the scene and options it was "
        "written with",
        name, frame.fingerprint, fingerprint_));
  }
  if (frame.step > cadence_.total) {
    throw ConfigError(fmt::format(
        "{}: holds t = {:.6g} s, beyond the run's duration of {:.6g} s; set `duration_s` to "
        "at least {:.6g} s",
        name, frame.time_s, duration_s_, frame.time_s));
  }
  scene::ByteReader in(frame.payload, name);
  engine_->RestoreCheckpoint(in);
  random_ = scene::SceneRandom(in.Get<std::uint64_t>());
  budget_->RestoreJoules(in.Get<double>());
  pending_ = GetParticles(in);
  summary_.history = in.GetVector<HistoryPoint>();
  earlier_wall_s_ = in.Get<double>();
  if (in.left() != 0 || engine_->steps() != frame.step) {
    in.Fail("its payload does not match its header");
  }
}

// Why the run cannot go on, if it cannot: a state that is no longer finite, a particle crossing
// half its radius per step, or kinetic energy the particles never brought in.
template <int Dim>
std::optional<std::string> PackingRun<Dim>::Instability() const {
  if (engine_->HasNonFiniteState()) {
    return fmt::format(
        "the run became unstable at t = {:.6g} s (a position or velocity is not finite); "
        "use a smaller time_step_s than {:.3g} s",
        engine_->time_s(), dt_);
  }
  const double limit_s = limits_.normal.limit_s;
  if (const double speed = MaxSpeedMps(engine_->state()); speed > runaway_speed_mps_) {
    return fmt::format(
        "the run became unstable at t = {:.6g} s: a particle reached {:.3g} m/s and moves more "
        "than half its radius per step; use a smaller time_step_s than {:.3g} s (the stability "
        "limit of one contact is {:.3g} s)",
        engine_->time_s(), speed, dt_, limit_s);
  }
  if (const double kinetic = engine_->KineticEnergyJ();
      budget_->bounded() &&
      kinetic > kEnergyBudgetFactor * budget_->joules() + std::numeric_limits<double>::min()) {
    return fmt::format(
        "the run became unstable at t = {:.6g} s: the particles hold {:.3g} J of kinetic energy, "
        "more than {:.0f} times the {:.3g} J they brought in (fall to the floor, launch, start "
        "overlaps, van der Waals), so the integrator is making energy; use a smaller "
        "time_step_s than {:.3g} s (several contacts stiffen a particle beyond the {:.3g} s "
        "limit of one)",
        engine_->time_s(), kinetic, kEnergyBudgetFactor, budget_->joules(), dt_, limit_s);
  }
  return std::nullopt;
}

template <int Dim>
void PackingRun<Dim>::PourBatch() {
  const auto placed = scene::PlaceInRegion(scene_, pending_, Existing(*engine_), random_);
  const std::int32_t first_new = engine_->state().size();
  Insert(*engine_, scene_, placed);
  budget_->AddInserted(*engine_, first_new);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(placed.size()));
}

// The history point and the snapshot due at `step`.
template <int Dim>
void PackingRun<Dim>::Record(std::int64_t step) {
  if (step % cadence_.history == 0 || step == cadence_.total) {
    summary_.history.push_back(Sample(Snapshot(*engine_), scene_, engine_->KineticEnergyJ()));
  }
  if (options_.snapshot && (step % cadence_.snapshot == 0 ||
                            (step == cadence_.total && cadence_.snapshot != StepCadence::never))) {
    options_.snapshot(Snapshot(*engine_));
  }
}

template <int Dim>
PackSummary PackingRun<Dim>::Run() && {
  if (options_.resume_checkpoint) Resume();
  if (options_.started) options_.started();
  if (!options_.resume_checkpoint && options_.snapshot && cadence_.snapshot != StepCadence::never) {
    options_.snapshot(Snapshot(*engine_));
  }
  std::int64_t particle_steps = 0;
  std::int64_t step = engine_->steps();
  std::int64_t next_checkpoint = NextMultiple(step, cadence_.checkpoint);
  WallTimeProjection projection(
      engine_->state().size() + static_cast<std::int64_t>(pending_.size()), cadence_.total,
      options_.threads, step, SecondsSince(start_));
  while (step < cadence_.total) {
    const std::int64_t target =
        std::min({cadence_.total, NextMultiple(step, cadence_.history),
                  NextMultiple(step, cadence_.snapshot), NextMultiple(step, cadence_.batch),
                  NextMultiple(step, cadence_.progress)});
    // A stop request ends the block at the step it arrives in (AdvanceUntil); the checkpoint
    // below then holds the pending kick that keeps a resumed run bit-identical.
    const std::int64_t taken = engine_->AdvanceUntil(target - step, options_.stop_requested);
    particle_steps += taken * engine_->state().size();
    step += taken;
    if (auto unstable = Instability()) {
      summary_.stop_reason = PackStopReason::kUnstable;
      summary_.message = std::move(*unstable);
      break;
    }
    if (step % cadence_.batch == 0 && !pending_.empty()) PourBatch();
    Record(step);
    if (options_.progress) {
      const double wall = SecondsSince(start_);
      options_.progress(PackProgress{engine_->time_s(), duration_s_, step, engine_->state().size(),
                                     wall, projection.Update(step, engine_->state().size(), wall)});
    }
    if (step < cadence_.total && options_.stop_requested && options_.stop_requested()) {
      SaveCheckpoint();
      summary_.stop_reason = PackStopReason::kInterrupted;
      break;
    }
    if (step < cadence_.total && step >= next_checkpoint) {
      SaveCheckpoint();
      next_checkpoint = NextMultiple(step, cadence_.checkpoint);
    }
  }
  Measure();
  summary_.wall_s = SecondsSince(start_);
  summary_.total_wall_s = earlier_wall_s_ + summary_.wall_s;
  summary_.particle_steps_per_s =
      summary_.wall_s > 0 ? static_cast<double>(particle_steps) / summary_.wall_s : 0.0;
  return std::move(summary_);
}

// The final state and its measures (none of an unstable run's), and the summary's sentence.
template <int Dim>
void PackingRun<Dim>::Measure() {
  summary_.final_state = Snapshot(*engine_);
  summary_.particles = engine_->state().size();
  summary_.particles_not_inserted = static_cast<std::int64_t>(pending_.size());
  summary_.steps = engine_->steps();
  summary_.neighbor_rebuilds = engine_->rebuilds();
  summary_.simulated_s = engine_->time_s();
  summary_.kinetic_energy_j = engine_->KineticEnergyJ();
  summary_.state_digest = StateDigest(engine_->state());
  if (summary_.stop_reason == PackStopReason::kUnstable) return;
  summary_.packing_density = PackingDensity(summary_.final_state, scene_);
  summary_.packing_density_by_count = CentreCountDensity(summary_.final_state, scene_);
  summary_.coordination = Coordination(summary_.final_state, scene_);
  const double bin = scene_.measurement.profile_bin_m > 0
                         ? scene_.measurement.profile_bin_m
                         : 0.25 * scene_.particles.diameter.MaxDiameterM();
  summary_.profile = DensityProfileVsHeight(summary_.final_state, scene_, bin);
  summary_.message =
      fmt::format("ran {} steps to t = {:.6g} s", summary_.steps, summary_.simulated_s);
  if (summary_.particles_not_inserted > 0) {
    summary_.message +=
        fmt::format("; {} particles never fit in the pour region", summary_.particles_not_inserted);
  }
  if (summary_.stop_reason == PackStopReason::kInterrupted) {
    summary_.message = fmt::format(
        "interrupted after {} steps at t = {:.6g} s of {:.6g} s; the measures describe that "
        "moment",
        summary_.steps, summary_.simulated_s, duration_s_);
  } else if (auto unsettled = scene::NotAtRest(summary_.history)) {
    summary_.warnings.push_back(*unsettled);
    summary_.boiling = scene::Boiling(summary_.history);
    // The summary's one sentence says why the run failed, not only how far it ran.
    if (summary_.boiling) summary_.message = scene::BoilingMessage(summary_.history, dt_);
  }
}

}  // namespace

PackSummary RunPacking(const Scene& scene, const PackOptions& options) {
  options.Validate();
  return scene.dimension == 2 ? PackingRun<2>(scene, options).Run()
                              : PackingRun<3>(scene, options).Run();
}

void WriteLammpsDump(std::ostream& out, const ParticleSnapshot& snap, const Scene& scene) {
  double lo[3] = {0, 0, 0};
  double hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < snap.size(); ++i) {
    for (int d = 0; d < 3; ++d) {
      const double x = snap.position_m[i][d];
      const double r = snap.radius_m[i];
      lo[d] = i == 0 ? x - r : std::min(lo[d], x - r);
      hi[d] = i == 0 ? x + r : std::max(hi[d], x + r);
    }
  }
  if (scene.dimension == 2) {  // a thin slab so 3D viewers show the disks
    const double r = scene.particles.diameter.MaxDiameterM() / 2;
    lo[2] = -r;
    hi[2] = r;
  }
  out << "ITEM: TIMESTEP\n"
      << snap.step << "\nITEM: NUMBER OF ATOMS\n"
      << snap.size() << "\nITEM: BOX BOUNDS ff ff ff\n";
  for (int d = 0; d < 3; ++d) out << fmt::format("{:.9g} {:.9g}\n", lo[d], hi[d]);
  out << "ITEM: ATOMS id type radius x y z vx vy vz\n";
  for (std::size_t i = 0; i < snap.size(); ++i) {
    const auto& x = snap.position_m[i];
    const auto& v = snap.velocity_mps[i];
    out << fmt::format("{} {} {:.9g} {:.9g} {:.9g} {:.9g} {:.6g} {:.6g} {:.6g}\n", i + 1,
                       snap.species[i] + 1, snap.radius_m[i], x[0], x[1], x[2], v[0], v[1], v[2]);
  }
}

void WriteLammpsData(std::ostream& out, const ParticleSnapshot& snap, const Scene& scene) {
  out << "LAMMPS data file written by bouncecal from " << scene.source.string() << "\n\n"
      << snap.size() << " atoms\n"
      << scene.particles.species.size() << " atom types\n";
  double lo[3] = {0, 0, 0};
  double hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < snap.size(); ++i) {
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], snap.position_m[i][d] - 2 * snap.radius_m[i]);
      hi[d] = std::max(hi[d], snap.position_m[i][d] + 2 * snap.radius_m[i]);
    }
  }
  // The box must hold the container too, or LAMMPS loses atoms that reach its walls.
  const auto& c = scene.container;
  const double margin = scene.particles.diameter.MaxDiameterM();
  if (c.kind == ContainerKind::kCylinder) {
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], c.center_m[d] - c.radius_m - margin);
      hi[d] = std::max(hi[d], c.center_m[d] + c.radius_m + margin);
    }
    lo[2] = std::min(lo[2], c.center_m[2] - margin);
    hi[2] = std::max(hi[2], c.center_m[2] + c.height_m + margin);
  } else if (c.kind == ContainerKind::kBox) {
    for (int d = 0; d < scene.dimension; ++d) {
      lo[d] = std::min(lo[d], c.min_m[d] - margin);
      hi[d] = std::max(hi[d], c.max_m[d] + margin);
    }
  }
  const char* axes[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) {
    if (scene.dimension == 2 && d == 2) {
      out << "-0.5 0.5 zlo zhi\n";
      continue;
    }
    out << fmt::format("{:.9g} {:.9g} {}lo {}hi\n", lo[d], hi[d], axes[d], axes[d]);
  }
  out << "\nAtoms # sphere\n\n";
  for (std::size_t i = 0; i < snap.size(); ++i) {
    const auto& x = snap.position_m[i];
    const auto species = static_cast<std::size_t>(snap.species[i]);
    out << fmt::format("{} {} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", i + 1, species + 1,
                       2 * snap.radius_m[i], scene.particles.species[species].density_kg_per_m3,
                       x[0], x[1], x[2]);
  }
}

}  // namespace bouncecal::dem
