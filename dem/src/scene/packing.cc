#include "bouncecal/dem/packing.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/pack_projection.h"
#include "bouncecal/error.h"
#include "scene/checkpoint_bytes.h"
#include "scene/contact_limits.h"
#include "scene/energy_budget.h"
#include "scene/engine.h"
#include "scene/insertion.h"
#include "scene/pack_checkpoint_file.h"
#include "scene/particle_file.h"
#include "scene/rest_checks.h"

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

template <int Dim>
PackSummary Run(const Scene& scene, const PackOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double container_height_m = ContainerTopM(scene) - ContainerFloorM(scene);
  if (scene.measurement.profile_bin_m > 0 && std::isfinite(container_height_m) &&
      container_height_m / scene.measurement.profile_bin_m > kMaxProfileBins) {
    throw ConfigError(fmt::format(
        "{}: measurement.profile_bin_m = {:.3g} m cuts the {:.3g} m tall container into more "
        "than {:.0f} bins; use a larger bin",
        scene.source.string(), scene.measurement.profile_bin_m, container_height_m,
        kMaxProfileBins));
  }
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
  settings.threads = options.threads;
  auto engine = scene::MakeEngine<Dim>(settings, scene::ContainerWalls<Dim>(scene.container), m.law,
                                       scene.physics);

  scene::SceneRandom random(scene.insertion.seed);
  std::vector<scene::NewParticle> pending;
  if (scene.insertion.kind == InsertionKind::kFile) {
    std::vector<scene::NewParticle> start;
    if (scene.insertion.start_particles.empty()) {
      start = scene::ReadParticleFile(scene.insertion.file, Dim);
    } else {
      for (const auto& p : scene.insertion.start_particles) {
        start.push_back({p.position_m, p.radius_m, p.species});
      }
    }
    Insert(*engine, scene, start);
  } else {
    pending = scene::DrawParticles(scene, random);
    const auto placed = scene::PlaceInRegion(scene, pending, {}, random);
    if (scene.insertion.kind == InsertionKind::kRandom && placed.size() < pending.size()) {
      throw ConfigError(fmt::format(
          "{}: insertion.region holds only {} of the {} particles without overlap after {} "
          "attempts; enlarge the region or raise insertion.max_attempts",
          scene.source.string(), placed.size(), pending.size(), scene.insertion.max_attempts));
    }
    Insert(*engine, scene, placed);
    pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(placed.size()));
  }

  const double dt = scene.time_step_s;
  const scene::BodyExtremes bodies = Extremes(*engine, scene, pending);
  if (const auto problem = scene::VanDerWaalsOverlapProblem(scene, bodies)) {
    throw ConfigError(scene.source.string() + ": " + *problem);
  }
  PackSummary summary;
  const scene::TimeStepLimits limits = scene::CheckTimeStep(
      scene, bodies, options.allow_unstable_step, summary.warnings, summary.notes);
  const scene::TimeStepLimit& limit = limits.normal;
  scene::EnergyBudget budget(scene, *engine,
                             engine->state().size() + static_cast<std::int64_t>(pending.size()));
  // A particle that moves half its radius in one step overlaps whatever it meets by that much
  // before any force acts: no contact is resolved any more, energy is created, particles pass
  // through walls. Stop there rather than run on to absurd (finite) numbers.
  const double runaway_speed_mps = 0.5 * SmallestRadiusM(*engine, pending) / dt;
  const double duration = options.duration_s.value_or(scene.duration_s);
  const std::int64_t total_steps = std::llround(duration / dt);
  const std::int64_t history_every = StepsFor(scene.measurement.history_interval_s, dt);
  const std::int64_t snapshot_every = StepsFor(scene.outputs.snapshot_interval_s, dt);
  const std::int64_t batch_every = scene.insertion.kind == InsertionKind::kPour
                                       ? StepsFor(scene.insertion.batch_interval_s, dt)
                                       : std::numeric_limits<std::int64_t>::max();
  const std::int64_t progress_every = options.progress_every_steps;

  summary.physics = DescribePhysics(scene);
  summary.time_step_s = dt;
  summary.time_step_limit_s = limit.limit_s;
  summary.tangential_time_step_limit_s = limits.tangential.limit_s;
  summary.threads = options.threads;
  summary.history.push_back(Sample(Snapshot(*engine), scene, engine->KineticEnergyJ()));
  const std::uint64_t fingerprint =
      SetupFingerprint(scene, settings, *engine, pending, random,
                       {history_every, snapshot_every, batch_every, progress_every});
  double earlier_wall_s = 0;  // of the runs before the checkpoint this one resumes
  auto save_checkpoint = [&] {
    if (!options.checkpoint) return;
    scene::ByteWriter payload;
    engine->SaveCheckpoint(payload);
    payload.Put(random.state());
    payload.Put(budget.joules());
    PutParticles(payload, pending);
    payload.PutVector(summary.history);
    // The wall time of the runs that led to this state, so that a resumed run reports the total.
    payload.Put(earlier_wall_s + SecondsSince(start));
    scene::PackCheckpointFrame frame;
    frame.dimension = Dim;
    frame.fingerprint = fingerprint;
    frame.step = engine->steps();
    frame.time_s = engine->time_s();
    frame.payload = payload.bytes();
    options.checkpoint(scene::WritePackCheckpointFrame(frame), engine->time_s());
  };
  if (options.resume_checkpoint) {
    const std::string& name = options.resume_name;
    const auto frame = scene::ReadPackCheckpointFrame(*options.resume_checkpoint, name);
    if (frame.dimension != Dim || frame.fingerprint != fingerprint) {
      throw InputError(fmt::format(
          "{}: was written for another scene or other options (its set-up fingerprint {:016x} "
          "is not this run's {:016x}: scene file, material, seed, start file, "
          "`skin_diameters`, `min_skin_diameters`); resume with the scene and options it was "
          "written with",
          name, frame.fingerprint, fingerprint));
    }
    if (frame.step > total_steps) {
      throw ConfigError(fmt::format(
          "{}: holds t = {:.6g} s, beyond the run's duration of {:.6g} s; set `duration_s` to "
          "at least {:.6g} s",
          name, frame.time_s, duration, frame.time_s));
    }
    scene::ByteReader in(frame.payload, name);
    engine->RestoreCheckpoint(in);
    random = scene::SceneRandom(in.Get<std::uint64_t>());
    budget.RestoreJoules(in.Get<double>());
    pending = GetParticles(in);
    summary.history = in.GetVector<HistoryPoint>();
    earlier_wall_s = in.Get<double>();
    if (in.left() != 0 || engine->steps() != frame.step) {
      in.Fail("its payload does not match its header");
    }
  }
  if (options.started) options.started();
  if (!options.resume_checkpoint && options.snapshot &&
      snapshot_every != std::numeric_limits<std::int64_t>::max()) {
    options.snapshot(Snapshot(*engine));
  }
  std::int64_t particle_steps = 0;
  auto next_multiple = [](std::int64_t step, std::int64_t every) {
    if (every == std::numeric_limits<std::int64_t>::max()) return every;
    return (step / every + 1) * every;
  };
  std::int64_t step = engine->steps();
  const std::int64_t checkpoint_every = options.checkpoint
                                            ? StepsFor(options.checkpoint_every_s, dt)
                                            : std::numeric_limits<std::int64_t>::max();
  std::int64_t next_checkpoint = next_multiple(step, checkpoint_every);
  WallTimeProjection projection(engine->state().size() + static_cast<std::int64_t>(pending.size()),
                                total_steps, options.threads, step, SecondsSince(start));
  while (step < total_steps) {
    const std::int64_t target = std::min(
        {total_steps, next_multiple(step, history_every), next_multiple(step, snapshot_every),
         next_multiple(step, batch_every), next_multiple(step, progress_every)});
    // A stop request ends the block at the step it arrives in (AdvanceUntil); the checkpoint
    // below then holds the pending kick that keeps a resumed run bit-identical.
    const std::int64_t taken = engine->AdvanceUntil(target - step, options.stop_requested);
    particle_steps += taken * engine->state().size();
    step += taken;
    if (engine->HasNonFiniteState()) {
      summary.stop_reason = PackStopReason::kUnstable;
      summary.message = fmt::format(
          "the run became unstable at t = {:.6g} s (a position or velocity is not finite); "
          "use a smaller time_step_s than {:.3g} s",
          engine->time_s(), dt);
      break;
    }
    if (const double speed = MaxSpeedMps(engine->state()); speed > runaway_speed_mps) {
      summary.stop_reason = PackStopReason::kUnstable;
      summary.message = fmt::format(
          "the run became unstable at t = {:.6g} s: a particle reached {:.3g} m/s and moves more "
          "than half its radius per step; use a smaller time_step_s than {:.3g} s (the stability "
          "limit of one contact is {:.3g} s)",
          engine->time_s(), speed, dt, limit.limit_s);
      break;
    }
    if (const double kinetic = engine->KineticEnergyJ();
        budget.bounded() &&
        kinetic > kEnergyBudgetFactor * budget.joules() + std::numeric_limits<double>::min()) {
      summary.stop_reason = PackStopReason::kUnstable;
      summary.message = fmt::format(
          "the run became unstable at t = {:.6g} s: the particles hold {:.3g} J of kinetic energy, "
          "more than {:.0f} times the {:.3g} J they brought in (fall to the floor, launch, start "
          "overlaps, van der Waals), so the integrator is making energy; use a smaller "
          "time_step_s than {:.3g} s (several contacts stiffen a particle beyond the {:.3g} s "
          "limit of one)",
          engine->time_s(), kinetic, kEnergyBudgetFactor, budget.joules(), dt, limit.limit_s);
      break;
    }
    if (step % batch_every == 0 && !pending.empty()) {
      const auto placed = scene::PlaceInRegion(scene, pending, Existing(*engine), random);
      const std::int32_t first_new = engine->state().size();
      Insert(*engine, scene, placed);
      budget.AddInserted(*engine, first_new);
      pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(placed.size()));
    }
    if (step % history_every == 0 || step == total_steps) {
      summary.history.push_back(Sample(Snapshot(*engine), scene, engine->KineticEnergyJ()));
    }
    if (options.snapshot &&
        (step % snapshot_every == 0 ||
         (step == total_steps && snapshot_every != std::numeric_limits<std::int64_t>::max()))) {
      options.snapshot(Snapshot(*engine));
    }
    if (options.progress) {
      const double wall = SecondsSince(start);
      options.progress(PackProgress{engine->time_s(), duration, step, engine->state().size(), wall,
                                    projection.Update(step, engine->state().size(), wall)});
    }
    if (step < total_steps && options.stop_requested && options.stop_requested()) {
      save_checkpoint();
      summary.stop_reason = PackStopReason::kInterrupted;
      break;
    }
    if (step < total_steps && step >= next_checkpoint) {
      save_checkpoint();
      next_checkpoint = next_multiple(step, checkpoint_every);
    }
  }

  summary.final_state = Snapshot(*engine);
  summary.particles = engine->state().size();
  summary.particles_not_inserted = static_cast<std::int64_t>(pending.size());
  summary.steps = engine->steps();
  summary.neighbor_rebuilds = engine->rebuilds();
  summary.simulated_s = engine->time_s();
  summary.kinetic_energy_j = engine->KineticEnergyJ();
  summary.state_digest = StateDigest(engine->state());
  if (summary.stop_reason != PackStopReason::kUnstable) {
    summary.packing_density = PackingDensity(summary.final_state, scene);
    summary.packing_density_by_count = CentreCountDensity(summary.final_state, scene);
    summary.coordination = Coordination(summary.final_state, scene);
    const double bin = scene.measurement.profile_bin_m > 0
                           ? scene.measurement.profile_bin_m
                           : 0.25 * scene.particles.diameter.MaxDiameterM();
    summary.profile = DensityProfileVsHeight(summary.final_state, scene, bin);
    summary.message =
        fmt::format("ran {} steps to t = {:.6g} s", summary.steps, summary.simulated_s);
    if (summary.particles_not_inserted > 0) {
      summary.message += fmt::format("; {} particles never fit in the pour region",
                                     summary.particles_not_inserted);
    }
    if (summary.stop_reason == PackStopReason::kInterrupted) {
      summary.message = fmt::format(
          "interrupted after {} steps at t = {:.6g} s of {:.6g} s; the measures describe that "
          "moment",
          summary.steps, summary.simulated_s, duration);
    } else if (auto unsettled = scene::NotAtRest(summary.history)) {
      summary.warnings.push_back(*unsettled);
      summary.boiling = scene::Boiling(summary.history);
      // The summary's one sentence says why the run failed, not only how far it ran.
      if (summary.boiling) summary.message = scene::BoilingMessage(summary.history, dt);
    }
  }
  summary.wall_s = SecondsSince(start);
  summary.total_wall_s = earlier_wall_s + summary.wall_s;
  summary.particle_steps_per_s =
      summary.wall_s > 0 ? static_cast<double>(particle_steps) / summary.wall_s : 0.0;
  return summary;
}

}  // namespace

PackSummary RunPacking(const Scene& scene, const PackOptions& options) {
  options.Validate();
  return scene.dimension == 2 ? Run<2>(scene, options) : Run<3>(scene, options);
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
