#include "bouncecal/dem/packing.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/error.h"
#include "scene/contact_limits.h"
#include "scene/energy_budget.h"
#include "scene/engine.h"
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
}

std::string_view ToString(PackStopReason reason) {
  switch (reason) {
    case PackStopReason::kDuration:
      return "duration";
    case PackStopReason::kUnstable:
      return "unstable";
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

// A packing is read at rest: kinetic energy at the end above this fraction of its peak means it
// was not (a pour at rest keeps ~1e-6 of it, paper 000 1.3e-5 J of ~10 J).
constexpr double kAtRestFraction = 1e-2;

// A warning when the run ended while its particles still moved: cut short, or boiling (a pack
// gaining energy from a coarse step as fast as its damping removes it stays under the energy
// budget but never settles).
std::optional<std::string> NotAtRest(const std::vector<HistoryPoint>& history) {
  if (history.size() < 2) return std::nullopt;
  const auto peak = std::max_element(history.begin(), history.end(),
                                     [](const HistoryPoint& a, const HistoryPoint& b) {
                                       return a.kinetic_energy_j < b.kinetic_energy_j;
                                     });
  const double last = history.back().kinetic_energy_j;
  if (!(peak->kinetic_energy_j > 0) || !(last > kAtRestFraction * peak->kinetic_energy_j)) {
    return std::nullopt;
  }
  return fmt::format(
      "the particles have not come to rest: the kinetic energy at the end, {:.3g} J, is {:.0f} % "
      "of its peak ({:.3g} J at t = {:.3g} s); the packing measures describe a moving state. Run "
      "longer, or, if it does not fall, use a smaller time_step_s",
      last, 100 * last / peak->kinetic_energy_j, peak->kinetic_energy_j, peak->time_s);
}

std::int64_t StepsFor(double interval_s, double dt) {
  if (!(interval_s > 0)) return std::numeric_limits<std::int64_t>::max();
  return std::max<std::int64_t>(1, std::llround(interval_s / dt));
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
    Insert(*engine, scene, scene::ReadParticleFile(scene.insertion.file, Dim));
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
  const scene::TimeStepLimits limits =
      scene::CheckTimeStep(scene, bodies, options.allow_unstable_step, summary.warnings);
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
  if (options.snapshot && snapshot_every != std::numeric_limits<std::int64_t>::max()) {
    options.snapshot(Snapshot(*engine));
  }
  std::int64_t particle_steps = 0;
  auto next_multiple = [](std::int64_t step, std::int64_t every) {
    if (every == std::numeric_limits<std::int64_t>::max()) return every;
    return (step / every + 1) * every;
  };
  std::int64_t step = 0;
  while (step < total_steps) {
    const std::int64_t target = std::min(
        {total_steps, next_multiple(step, history_every), next_multiple(step, snapshot_every),
         next_multiple(step, batch_every), next_multiple(step, progress_every)});
    engine->Advance(target - step);
    particle_steps += (target - step) * engine->state().size();
    step = target;
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
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      options.progress(
          PackProgress{engine->time_s(), duration, step, engine->state().size(), wall});
    }
  }

  summary.final_state = Snapshot(*engine);
  summary.particles = engine->state().size();
  summary.particles_not_inserted = static_cast<std::int64_t>(pending.size());
  summary.steps = engine->steps();
  summary.neighbor_rebuilds = engine->rebuilds();
  summary.simulated_s = engine->time_s();
  summary.kinetic_energy_j = engine->KineticEnergyJ();
  if (summary.stop_reason == PackStopReason::kDuration) {
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
    if (auto unsettled = NotAtRest(summary.history)) summary.warnings.push_back(*unsettled);
  }
  summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
