#include "bouncecal/calibrate/export/packing_deck.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouncecal/error.h"
#include "bouncecal/version.h"
#include "deck_text.h"

namespace bouncecal::calibrate {
namespace {

using deck_text::CommentBlock;
using deck_text::Number;
using deck_text::RequirePositive;

void RequireNonNegative(double value, std::string_view name) {
  if (!std::isfinite(value) || value < 0) {
    throw ConfigError(fmt::format("{} must be a finite number >= 0, got {}", name, value));
  }
}

void Validate(const PackingDeckSpec& spec, const PackingDeckOptions& options) {
  if (options.engine != Engine::kLammps) {
    throw ConfigError(
        "the packing-scene deck is written for lammps only so far (LIGGGHTS needs its own "
        "insertion and wall commands); use --engine lammps, or export the single-drop deck");
  }
  if (options.processes < 1 || options.processes > 4096) {
    throw ConfigError(
        fmt::format("MPI process count must be in [1, 4096], got {}", options.processes));
  }
  if (spec.particle_count < 1 || spec.particle_count > 1'000'000'000) {
    throw ConfigError(
        fmt::format("scene particle count must be in [1, 1e9], got {}", spec.particle_count));
  }
  RequirePositive(spec.diameter_m, "scene particle diameter", "metres");
  RequirePositive(spec.density_kg_per_m3, "scene particle density", "kg/m^3");
  RequirePositive(spec.container_height_m, "scene container height", "metres");
  if (spec.container == PackingContainer::kCylinder) {
    RequirePositive(spec.container_radius_m - spec.diameter_m,
                    "scene container radius minus one diameter", "metres");
  } else {
    RequirePositive(spec.box_half_x_m - spec.diameter_m,
                    "scene box half-width x minus one diameter", "metres");
    RequirePositive(spec.box_half_y_m - spec.diameter_m,
                    "scene box half-width y minus one diameter", "metres");
  }
  RequirePositive(spec.insert_z_min_m - 0.5 * spec.diameter_m,
                  "scene insertion bottom above the floor (minus a radius)", "metres");
  RequirePositive(spec.insert_z_max_m - spec.insert_z_min_m - spec.diameter_m,
                  "scene insertion band height minus one diameter", "metres");
  RequireNonNegative(spec.tangential_stiffness_n_per_m, "scene tangential stiffness (N/m)");
  RequireNonNegative(spec.friction, "scene friction");
  RequireNonNegative(spec.wall_friction, "scene wall friction");
  RequirePositive(spec.time_step_s, "scene time step", "seconds");
  RequirePositive(spec.duration_s, "scene duration", "seconds");
  RequirePositive(spec.gravity_mps2, "scene gravity", "m/s^2");
  RequireNonNegative(spec.snapshot_interval_s, "scene snapshot interval (s)");
  if (spec.seed == 0) throw ConfigError("scene seed must be a positive integer for fix pour");
}

}  // namespace

Deck MakePackingDeck(const ExportMaterial& material, const PackingDeckSpec& spec,
                     const PackingDeckOptions& options) {
  Validate(spec, options);
  const double d = spec.diameter_m;
  const double mass = spec.density_kg_per_m3 * std::numbers::pi * d * d * d / 6;
  // The pour's typical first impact: a fall from the middle of the insertion band.
  const double impact_speed =
      std::sqrt(2 * spec.gravity_mps2 * 0.5 * (spec.insert_z_min_m + spec.insert_z_max_m));
  const LawMapping mapping =
      MapContactLaw(material.law, mass, 0.5 * d, impact_speed, options.engine);

  Deck deck;
  deck.input_file_name = "in.pack";
  deck.time_step_s = spec.time_step_s;
  deck.duration_s = spec.duration_s;
  deck.steps = static_cast<std::int64_t>(std::ceil(spec.duration_s / spec.time_step_s));
  deck.trajectory_file_name = "final.data";
  deck.expected_restitution = mapping.restitution;
  const SpringDashpot& pair = mapping.pair;
  const double pair_contact_s = ContactDurationS(pair);
  // The shortest contact (pairs) sets both the discretisation error and the stability limit.
  deck.time_step_error_bound = pair.damping_rate_per_s * spec.time_step_s;
  const double omega_dt =
      std::sqrt(pair.stiffness_n_per_m / pair.effective_mass_kg) * spec.time_step_s;
  if (omega_dt >= 2) {
    throw ConfigError(fmt::format(
        "scene time step {} s is unstable for the mapped pair contact (omega dt = {:.3g} >= 2, "
        "t_c = {:.3g} s); use a step below {:.3g} s",
        spec.time_step_s, omega_dt, pair_contact_s, pair_contact_s / 20));
  }
  deck.output_every_steps =
      spec.snapshot_interval_s > 0
          ? std::max(1, static_cast<int>(std::lround(spec.snapshot_interval_s / spec.time_step_s)))
          : 0;
  deck.output_interval_s = deck.output_every_steps * spec.time_step_s;

  deck.notes = mapping.notes;
  deck.notes.push_back(fmt::format(
      "Time step {} s resolves a pair contact (t_c = {:.4g} s) in {:.1f} steps and a wall contact "
      "in {:.1f}: the restitution of single contacts may deviate by up to gamma_n dt = {:.1f} % "
      "(pairs){}.",
      Number(spec.time_step_s), pair_contact_s, pair_contact_s / spec.time_step_s,
      ContactDurationS(mapping.wall) / spec.time_step_s, 100 * deck.time_step_error_bound,
      deck.time_step_error_bound > 0.05
          ? "; with so few steps per contact e scatters from bounce to bounce (PHYSICS.md "
            "section 4: 0.47-0.58 for 0.577 at 10 us), which matters for dynamics more than for "
            "the final packing"
          : ""));
  deck.notes.push_back(fmt::format(
      "Tangential: Cundall-Strack spring kt = {} N/m with Coulomb friction {} (particles) and {} "
      "(walls), no tangential damping; nve/sphere integrates rotation.",
      Number(spec.tangential_stiffness_n_per_m), Number(spec.friction),
      Number(spec.wall_friction)));
  if (options.engine == Engine::kLammps) {
    deck.notes.push_back(
        "Insertion uses fix pour (LAMMPS 29Sep2021's create_atoms cannot avoid overlaps): "
        "particles appear without overlap in the insertion band and fall; later batches follow "
        "when the band has emptied, so a large count may need a longer run than the scene's "
        "duration to be fully inserted (thermo prints the atom count).");
  }

  const std::string executable(EngineExecutable(options.engine));
  deck.run_command =
      options.processes > 1
          ? fmt::format("mpirun -np {} {} -in {} -log log.lammps", options.processes, executable,
                        deck.input_file_name)
          : fmt::format("{} -in {} -log log.lammps", executable, deck.input_file_name);

  std::vector<std::string> header = {
      fmt::format("bouncecal packing-scene deck '{}' for lammps (LAMMPS 29Sep2021 or later, "
                  "GRANULAR package)",
                  spec.name),
      fmt::format("Written by bouncecal {} from material card: {}", Version(), material.source),
      fmt::format("Scene: {}", options.scene_source),
      fmt::format("Card's contact law: {}", mapping.source_description),
      fmt::format("Particles: {} spheres of {} m, {} kg/m^3 ({} kg each); {} s of {} s steps "
                  "({} steps); g = {} m/s^2.",
                  spec.particle_count, Number(d), Number(spec.density_kg_per_m3), Number(mass),
                  Number(spec.duration_s), Number(spec.time_step_s), deck.steps,
                  Number(spec.gravity_mps2)),
      ""};
  for (const auto& note : deck.notes) header.push_back(note);
  header.push_back("");
  header.push_back(
      fmt::format("Outputs: log.lammps (thermo: atoms, kinetic energy), {}final.data "
                  "(write_data of the final packing).",
                  deck.output_every_steps > 0
                      ? fmt::format("dump.pack (every {} s), ", Number(deck.output_interval_s))
                      : ""));
  header.push_back(fmt::format("Run in this folder: {}", deck.run_command));

  const double top = std::max(spec.container_height_m, spec.insert_z_max_m) + d;
  std::string box_region, wall_sides, insert_region;
  const std::string wall_law =
      fmt::format("hooke/history {} {} {} 0 {} 0", Number(mapping.wall.stiffness_n_per_m),
                  Number(spec.tangential_stiffness_n_per_m),
                  Number(mapping.wall.damping_rate_per_s), Number(spec.wall_friction));
  if (spec.container == PackingContainer::kCylinder) {
    const double r = spec.container_radius_m;
    box_region = fmt::format("block {} {} {} {} {} {}", Number(-r - d), Number(r + d),
                             Number(-r - d), Number(r + d), Number(-d), Number(top));
    wall_sides =
        fmt::format("fix             side all wall/gran {} zcylinder {}\n", wall_law, Number(r));
    insert_region = fmt::format("cylinder z 0 0 {} {} {}", Number(r - d),
                                Number(spec.insert_z_min_m), Number(spec.insert_z_max_m));
  } else {
    const double x = spec.box_half_x_m, y = spec.box_half_y_m;
    box_region = fmt::format("block {} {} {} {} {} {}", Number(-x - d), Number(x + d),
                             Number(-y - d), Number(y + d), Number(-d), Number(top));
    wall_sides = fmt::format(
        "fix             side_x all wall/gran {0} xplane {1} {2}\n"
        "fix             side_y all wall/gran {0} yplane {3} {4}\n",
        wall_law, Number(-x), Number(x), Number(-y), Number(y));
    insert_region =
        fmt::format("block {} {} {} {} {} {}", Number(-x + d), Number(x - d), Number(-y + d),
                    Number(y - d), Number(spec.insert_z_min_m), Number(spec.insert_z_max_m));
  }

  std::string script = CommentBlock(header);
  script += fmt::format(
      R"(
units           si
atom_style      sphere
dimension       3
boundary        f f f
newton          off
comm_modify     vel yes

region          box {box} units box
create_box      1 box

# Pair contacts (equal spheres, m_eff = m/2): Kn Kt gamma_n gamma_t xmu dampflag.
pair_style      gran/hooke/history {kn} {kt} {gn} 0 {mu} 0
pair_coeff      * *
neighbor        {skin} bin
neigh_modify    delay 0

timestep        {dt}
fix             integrate all nve/sphere
fix             gravity all gravity {g} vector 0 0 -1
# Wall contacts (sphere on wall, m_eff = m): the contact the drop calibration measured.
fix             floor all wall/gran {wall} zplane 0.0 NULL
{sides}
region          insert {insert} units box
fix             pour all pour {count} 1 {seed} region insert diam one {d} dens {rho} {rho}

compute         rotation all erotate/sphere
thermo_style    custom step time atoms ke c_rotation
thermo          {thermo}
{dump}run             {steps}
write_data      final.data
)",
      fmt::arg("box", box_region), fmt::arg("kn", Number(pair.stiffness_n_per_m)),
      fmt::arg("kt", Number(spec.tangential_stiffness_n_per_m)),
      fmt::arg("gn", Number(pair.damping_rate_per_s)), fmt::arg("mu", Number(spec.friction)),
      fmt::arg("skin", Number(0.2 * d)), fmt::arg("dt", Number(spec.time_step_s)),
      fmt::arg("g", Number(spec.gravity_mps2)), fmt::arg("wall", wall_law),
      fmt::arg("sides", wall_sides), fmt::arg("insert", insert_region),
      fmt::arg("count", spec.particle_count), fmt::arg("seed", spec.seed), fmt::arg("d", Number(d)),
      fmt::arg("rho", Number(spec.density_kg_per_m3)),
      fmt::arg("thermo", std::max<std::int64_t>(1, deck.steps / 20)),
      fmt::arg("dump",
               deck.output_every_steps > 0
                   ? fmt::format("dump            snapshots all custom {} dump.pack id type "
                                 "radius x y z vx vy vz\n",
                                 deck.output_every_steps)
                   : std::string()),
      fmt::arg("steps", deck.steps));
  deck.files.push_back({deck.input_file_name, script});
  return deck;
}

}  // namespace bouncecal::calibrate
