#include "bouncecal/export/packing_deck.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouncecal/error.h"
#include "bouncecal/version.h"
#include "deck_preamble.h"
#include "deck_text.h"

namespace bouncecal::calibrate {
namespace {

using deck_text::CommentBlock;
using deck_text::LammpsPreamble;
using deck_text::LiggghtsPreamble;
using deck_text::Number;
using deck_text::RequirePositive;

double LargestDiameter(const PackingDeckSpec& spec) {
  return spec.max_diameter_m.value_or(spec.diameter_m);
}

double MeanDiameter(const PackingDeckSpec& spec) {
  return 0.5 * (spec.diameter_m + LargestDiameter(spec));
}

// E[d^3] of the uniform diameter distribution, for volumes.
double MeanCubedDiameter(const PackingDeckSpec& spec) {
  const double a = spec.diameter_m, b = LargestDiameter(spec);
  return b > a ? (std::pow(b, 4) - std::pow(a, 4)) / (4 * (b - a)) : a * a * a;
}

double SphereMass(double diameter_m, double density_kg_per_m3) {
  return density_kg_per_m3 * std::numbers::pi * std::pow(diameter_m, 3) / 6;
}

void RequireNonNegative(double value, std::string_view name) {
  if (!std::isfinite(value) || value < 0) {
    throw ConfigError(fmt::format("{} must be a finite number >= 0, got {}", name, value));
  }
}

// The scene's insertion region: as given, or the container's section less one diameter.
struct InsertionRegion {
  double radius_m = 0;  // kCylinder
  double half_x_m = 0;  // kBox
  double half_y_m = 0;
};

InsertionRegion ScenesInsertionRegion(const PackingDeckSpec& spec) {
  const double d = LargestDiameter(spec);
  InsertionRegion region;
  region.radius_m = spec.insert_radius_m.value_or(spec.container_radius_m - d);
  region.half_x_m = spec.insert_half_x_m.value_or(spec.box_half_x_m - d);
  region.half_y_m = spec.insert_half_y_m.value_or(spec.box_half_y_m - d);
  return region;
}

// A start sphere must lie inside the container as bouncecal's engine places it: its centre at
// least a radius from every wall (a tolerance of 1e-9 m for the digits of a round trip).
void CheckStartSphere(const PackingDeckSpec& spec, const StartSphere& sphere) {
  const double r = 0.5 * sphere.diameter_m;
  constexpr double kSlackM = 1e-9;
  const bool finite = std::isfinite(sphere.x_m) && std::isfinite(sphere.y_m) &&
                      std::isfinite(sphere.z_m) && std::isfinite(sphere.diameter_m);
  bool inside = finite && sphere.diameter_m > 0 && sphere.z_m >= r - kSlackM;
  if (spec.container == PackingContainer::kCylinder) {
    inside = inside && std::hypot(sphere.x_m, sphere.y_m) <= spec.container_radius_m - r + kSlackM;
  } else {
    inside = inside && std::abs(sphere.x_m) <= spec.box_half_x_m - r + kSlackM &&
             std::abs(sphere.y_m) <= spec.box_half_y_m - r + kSlackM;
  }
  if (!inside) {
    throw ConfigError(fmt::format(
        "start sphere at ({}, {}, {}) m of diameter {} m is not a radius inside the container; "
        "place every centre at least a radius from the floor and the walls",
        sphere.x_m, sphere.y_m, sphere.z_m, sphere.diameter_m));
  }
}

void Validate(const PackingDeckSpec& spec, const PackingDeckOptions& options) {
  if (options.processes < 1 || options.processes > 4096) {
    throw ConfigError(
        fmt::format("MPI process count must be in [1, 4096], got {}", options.processes));
  }
  if (spec.particle_count < 1 || spec.particle_count > 1'000'000'000) {
    throw ConfigError(
        fmt::format("scene particle count must be in [1, 1e9], got {}", spec.particle_count));
  }
  RequirePositive(spec.diameter_m, "scene particle diameter", "metres");
  if (spec.max_diameter_m && !(*spec.max_diameter_m > spec.diameter_m)) {
    throw ConfigError(fmt::format(
        "scene largest diameter must exceed the smallest ({} m), got {}; leave it unset for one "
        "size",
        spec.diameter_m, *spec.max_diameter_m));
  }
  const double largest = LargestDiameter(spec);
  RequirePositive(spec.density_kg_per_m3, "scene particle density", "kg/m^3");
  RequirePositive(spec.container_height_m, "scene container height", "metres");
  if (spec.container == PackingContainer::kCylinder) {
    RequirePositive(spec.container_radius_m - largest, "scene container radius minus one diameter",
                    "metres");
  } else {
    RequirePositive(spec.box_half_x_m - largest, "scene box half-width x minus one diameter",
                    "metres");
    RequirePositive(spec.box_half_y_m - largest, "scene box half-width y minus one diameter",
                    "metres");
  }
  if (spec.dimension != 2 && spec.dimension != 3) {
    throw ConfigError(fmt::format("scene dimension must be 2 or 3, got {}", spec.dimension));
  }
  if (spec.dimension == 2) {
    if (options.engine != Engine::kLammps) {
      throw ConfigError(
          "2D packing decks are written for LAMMPS only (dimension 2, enforce2d); "
          "choose `engine=lammps`");
    }
    if (spec.container != PackingContainer::kBox || !spec.start_data) {
      throw ConfigError("a 2D packing deck needs a box container and start positions");
    }
    if (spec.max_diameter_m) {
      throw ConfigError(
          "2D packing decks take one particle size; leave the largest diameter unset");
    }
  }
  if (spec.start_data && spec.start_data->empty()) {
    throw ConfigError("scene start positions are empty; give a LAMMPS data file's text");
  }
  if (!spec.start_data) {
    RequirePositive(spec.insert_z_min_m - 0.5 * largest,
                    "scene insertion bottom above the floor (minus a radius)", "metres");
    RequirePositive(spec.insert_z_max_m - spec.insert_z_min_m - largest,
                    "scene insertion band height minus one diameter", "metres");
  }
  // The insertion region must hold a particle and stay inside the container's walls.
  auto check_inside = [&](const std::optional<double>& value, double wall, std::string_view name) {
    if (!value) return;
    RequirePositive(*value - 0.5 * largest, fmt::format("{} minus a radius", name), "metres");
    RequirePositive(wall - *value, fmt::format("container size minus {}", name), "metres");
  };
  check_inside(spec.insert_radius_m, spec.container_radius_m, "scene insertion radius");
  check_inside(spec.insert_half_x_m, spec.box_half_x_m, "scene insertion half-width x");
  check_inside(spec.insert_half_y_m, spec.box_half_y_m, "scene insertion half-width y");
  if (!spec.start_data) {
    // Poured centres keep a largest radius inside the region: there must be room for them.
    const InsertionRegion region = ScenesInsertionRegion(spec);
    const double r = 0.5 * largest;
    if (spec.container == PackingContainer::kCylinder) {
      RequirePositive(region.radius_m - r, "scene insertion radius minus a radius", "metres");
    } else {
      RequirePositive(region.half_x_m - r, "scene insertion half-width x minus a radius", "metres");
      RequirePositive(region.half_y_m - r, "scene insertion half-width y minus a radius", "metres");
    }
  }
  if (spec.dimension == 3 && spec.start_data) {
    throw ConfigError(
        "3D packing decks take their start as start_spheres; start_data is for 2D decks");
  }
  if (static_cast<std::int64_t>(spec.start_spheres.size()) > spec.particle_count) {
    throw ConfigError(fmt::format("{} start spheres for a scene of {} particles; give at most {}",
                                  spec.start_spheres.size(), spec.particle_count,
                                  spec.particle_count));
  }
  if (spec.dimension == 2 && !spec.start_spheres.empty()) {
    throw ConfigError("2D packing decks take their start as start_data, not start_spheres");
  }
  for (const auto& sphere : spec.start_spheres) CheckStartSphere(spec, sphere);
  if (spec.batch_interval_s) {
    RequirePositive(*spec.batch_interval_s, "scene batch interval", "seconds");
  }
  RequireNonNegative(spec.tangential_stiffness_n_per_m, "scene tangential stiffness (N/m)");
  RequireNonNegative(spec.friction, "scene friction");
  RequireNonNegative(spec.wall_friction, "scene wall friction");
  RequirePositive(spec.time_step_s, "scene time step", "seconds");
  RequirePositive(spec.duration_s, "scene duration", "seconds");
  RequirePositive(spec.gravity_mps2, "scene gravity", "m/s^2");
  RequireNonNegative(spec.snapshot_interval_s, "scene snapshot interval (s)");
  if (spec.seed == 0) throw ConfigError("scene seed must be a positive integer for fix pour");
}

// LIGGGHTS wants prime seeds above 10000 for its random generators.
std::uint32_t PrimeSeed(std::uint32_t seed) {
  auto is_prime = [](std::uint32_t n) {
    for (std::uint32_t f = 2; f * f <= n; ++f) {
      if (n % f == 0) return false;
    }
    return n > 1;
  };
  std::uint32_t candidate = 10007 + seed % 1'000'000;
  while (!is_prime(candidate)) ++candidate;
  return candidate;
}

// The particles the deck pours (those not in the start): how many, from which step, in batches
// of what size how often. A batch is as large as bouncecal's first one (its engine fills the
// region at t = 0), or a quarter of the band's volume without a start; batches come every
// batch_interval_s of the scene, or every fall time through the band.
struct PourPlan {
  std::int64_t count = 0;
  std::int64_t first_step = 0;  // the pour begins after this many steps
  std::int64_t every_steps = 1;
  std::int64_t per_batch = 1;
};

double SectionArea(const PackingDeckSpec& spec, const InsertionRegion& region) {
  return spec.container == PackingContainer::kCylinder
             ? std::numbers::pi * region.radius_m * region.radius_m
             : 4 * region.half_x_m * region.half_y_m;
}

PourPlan PlanPour(const PackingDeckSpec& spec) {
  PourPlan plan;
  const auto started = static_cast<std::int64_t>(spec.start_spheres.size());
  plan.count = spec.particle_count - started;
  const double band = spec.insert_z_max_m - spec.insert_z_min_m;
  const double particle_volume = std::numbers::pi * MeanCubedDiameter(spec) / 6;
  const double interval_s = spec.batch_interval_s.value_or(std::sqrt(2 * band / spec.gravity_mps2));
  plan.every_steps = std::max<std::int64_t>(1, std::llround(interval_s / spec.time_step_s));
  plan.first_step = started > 0 ? plan.every_steps : 0;
  const auto quarter = static_cast<std::int64_t>(
      0.25 * SectionArea(spec, ScenesInsertionRegion(spec)) * band / particle_volume);
  plan.per_batch = std::clamp<std::int64_t>(started > 0 ? started : quarter, 1,
                                            std::max<std::int64_t>(1, plan.count));
  return plan;
}

// The simulation box (the container plus one diameter of margin, up to the top of the pour) and
// the insertion regions, in LAMMPS/LIGGGHTS region syntax (both accept the same): the scene's
// (LIGGGHTS' all_in keeps whole particles inside it) and the one its centres may take, a largest
// radius inside it (LAMMPS' fix pour draws centres anywhere in its region).
struct Regions {
  std::string box;
  std::string insert;
  std::string centres;
  double box_lo[3] = {0, 0, 0};
  double box_hi[3] = {0, 0, 0};
  double centres_volume_m3 = 0;  // as fix pour counts it (a block thinner than 1 in y: 1)
  double centres_band_m = 0;     // fix pour's fall through it sets its batch interval
};

Regions MakeRegions(const PackingDeckSpec& spec) {
  const double d = LargestDiameter(spec);
  const double r = 0.5 * d;
  const double top = std::max(spec.container_height_m, spec.insert_z_max_m) + d;
  const InsertionRegion region = ScenesInsertionRegion(spec);
  const std::string z_band =
      fmt::format("{} {}", Number(spec.insert_z_min_m), Number(spec.insert_z_max_m));
  const std::string z_centres =
      fmt::format("{} {}", Number(spec.insert_z_min_m + r), Number(spec.insert_z_max_m - r));
  Regions regions;
  regions.centres_band_m = spec.insert_z_max_m - spec.insert_z_min_m - d;
  const double half_x =
      spec.container == PackingContainer::kCylinder ? spec.container_radius_m : spec.box_half_x_m;
  const double half_y =
      spec.container == PackingContainer::kCylinder ? spec.container_radius_m : spec.box_half_y_m;
  regions.box_lo[0] = -half_x - d;
  regions.box_hi[0] = half_x + d;
  regions.box_lo[1] = -half_y - d;
  regions.box_hi[1] = half_y + d;
  regions.box_lo[2] = -d;
  regions.box_hi[2] = top;
  regions.box =
      fmt::format("block {} {} {} {} {} {}", Number(regions.box_lo[0]), Number(regions.box_hi[0]),
                  Number(regions.box_lo[1]), Number(regions.box_hi[1]), Number(regions.box_lo[2]),
                  Number(regions.box_hi[2]));
  if (spec.container == PackingContainer::kCylinder) {
    regions.insert = fmt::format("cylinder z 0 0 {} {}", Number(region.radius_m), z_band);
    regions.centres = fmt::format("cylinder z 0 0 {} {}", Number(region.radius_m - r), z_centres);
    regions.centres_volume_m3 =
        std::numbers::pi * std::pow(region.radius_m - r, 2) * regions.centres_band_m;
  } else {
    const double ix = region.half_x_m, iy = region.half_y_m;
    regions.insert = fmt::format("block {} {} {} {} {}", Number(-ix), Number(ix), Number(-iy),
                                 Number(iy), z_band);
    regions.centres = fmt::format("block {} {} {} {} {}", Number(-(ix - r)), Number(ix - r),
                                  Number(-(iy - r)), Number(iy - r), z_centres);
    regions.centres_volume_m3 = 2 * (ix - r) * std::max(1.0, 2 * (iy - r)) * regions.centres_band_m;
  }
  return regions;
}

// The start spheres as a LAMMPS data file (atom_style sphere; LIGGGHTS' granular reads the same
// columns) whose box is the simulation box. LIGGGHTS declares the wall type too.
std::string StartDataFile(const PackingDeckSpec& spec, const Regions& regions, bool lammps) {
  std::string text = fmt::format(
      "bouncecal start: the spheres bouncecal's engine places at t = 0 for scene '{}'\n\n"
      "{} atoms\n{} atom types\n\n",
      spec.name, spec.start_spheres.size(), lammps ? 1 : 2);
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    text += fmt::format("{} {} {}lo {}hi\n", Number(regions.box_lo[a]), Number(regions.box_hi[a]),
                        axes[a], axes[a]);
  }
  text += lammps ? "\nAtoms # sphere\n\n" : "\nAtoms\n\n";
  std::int64_t id = 0;
  for (const auto& sphere : spec.start_spheres) {
    text += fmt::format("{} 1 {} {} {} {} {}\n", ++id, Number(sphere.diameter_m),
                        Number(spec.density_kg_per_m3), Number(sphere.x_m), Number(sphere.y_m),
                        Number(sphere.z_m));
  }
  return text;
}

// Kinetic energies summed from the particles' own velocities and spins: thermo's `ke` keyword
// derives it from a temperature whose degrees of freedom are counted once, before any particle
// is poured, and prints -0.
std::string ThermoCommands(const Deck& deck) {
  return fmt::format(
      "compute         translation all ke\n"
      "compute         rotation all erotate/sphere\n"
      "thermo_style    custom step time atoms c_translation c_rotation\n"
      "thermo          {}\n",
      std::max<std::int64_t>(1, deck.steps / 20));
}

// Snapshots of every particle in LAMMPS' text dump format (both engines take the same command),
// the format bouncecal pack writes too, readable by OVITO and ParaView.
std::string DumpCommand(const Deck& deck) {
  return fmt::format(
      "dump            snapshots all custom {} dump.pack id type radius x y z vx vy vz\n",
      deck.output_every_steps);
}

// The run: the pour is defined when its first batch is due (at once without a start, after the
// scene's batch interval after one), so that both engines follow bouncecal's schedule.
std::string RunCommands(const PourPlan& plan, const std::string& pour, const Deck& deck) {
  std::string text = DumpCommand(deck);
  if (plan.count == 0 || plan.first_step >= deck.steps) {
    return text + fmt::format("run             {}\nwrite_data      final.data\n", deck.steps);
  }
  if (plan.first_step == 0) {
    return pour + text +
           fmt::format("run             {}\nwrite_data      final.data\n", deck.steps);
  }
  return text + fmt::format("run             {}\n", plan.first_step) + pour +
         fmt::format("run             {}\nwrite_data      final.data\n",
                     deck.steps - plan.first_step);
}

// Type 1 is the particle, type 2 the walls; property/global matrices are ordered 11 12 21 22.
std::string LiggghtsPackingScript(const PackingDeckSpec& spec, const LawMapping& mapping,
                                  const PourPlan& plan, const Regions& regions, const Deck& deck) {
  const double d = LargestDiameter(spec);
  // A uniform diameter distribution becomes kSizeClasses equally likely sizes at the centres of
  // equal-width bins (number-based weights), the closest LIGGGHTS' discrete templates come.
  constexpr int kSizeClasses = 5;
  const int classes = spec.max_diameter_m ? kSizeClasses : 1;
  std::string templates, weights;
  const std::uint32_t template_seeds[kSizeClasses] = {15485863, 15485867, 32452843, 32452867,
                                                      49979687};
  for (int i = 0; i < classes; ++i) {
    const double diameter =
        spec.diameter_m + (i + 0.5) / classes * (LargestDiameter(spec) - spec.diameter_m);
    templates += fmt::format(
        "fix             template{} all particletemplate/sphere {} atom_type 1 density constant "
        "{} radius constant {}\n",
        i + 1, template_seeds[i], Number(spec.density_kg_per_m3), Number(0.5 * diameter));
    weights += fmt::format(" template{} {}", i + 1, Number(1.0 / classes));
  }
  auto per_type_pair = [](double particle, double wall) {
    return fmt::format("{0} {1} {1} {1}", Number(particle), Number(wall));
  };
  const std::string wall_model =
      "wall/gran model hooke/stiffness tangential history primitive type 2";
  std::string walls;
  if (spec.container == PackingContainer::kCylinder) {
    walls = fmt::format("fix             side all {} zcylinder {} 0 0\n", wall_model,
                        Number(spec.container_radius_m));
  } else {
    const double x = spec.box_half_x_m, y = spec.box_half_y_m;
    walls = fmt::format(
        "fix             side_xlo all {0} xplane {1}\n"
        "fix             side_xhi all {0} xplane {2}\n"
        "fix             side_ylo all {0} yplane {3}\n"
        "fix             side_yhi all {0} yplane {4}\n",
        wall_model, Number(-x), Number(x), Number(-y), Number(y));
  }
  const std::string box = spec.start_spheres.empty() ? fmt::format(
                                                           "region          box {} units box\n"
                                                           "create_box      2 box\n",
                                                           regions.box)
                                                     : "read_data       start.data\n";
  // all_in yes keeps each whole particle inside the region, as bouncecal places it.
  const double rate_per_s =
      static_cast<double>(plan.per_batch) / (plan.every_steps * spec.time_step_s);
  const std::string pour = fmt::format(
      "{templates}fix             distribution all particledistribution/discrete/numberbased "
      "67867967 {classes}{weights}\n"
      "region          insert {insert} units box\n"
      "fix             pour all insert/rate/region seed {seed} distributiontemplate distribution "
      "nparticles {count} particlerate {rate} insert_every {every} overlapcheck yes all_in yes "
      "vel constant 0 0 0 region insert\n",
      fmt::arg("templates", templates), fmt::arg("classes", classes), fmt::arg("weights", weights),
      fmt::arg("insert", regions.insert), fmt::arg("seed", PrimeSeed(spec.seed)),
      fmt::arg("count", plan.count), fmt::arg("rate", Number(rate_per_s)),
      fmt::arg("every", plan.every_steps));
  return fmt::format(
      R"(
{preamble}
{box}neighbor        {skin} bin
neigh_modify    delay 0

# model hooke/stiffness (absolute_damping off): F = kn xi + m_eff gamman dxi/dt; tangential
# history: Cundall-Strack spring kt capped by coefficientFriction, no tangential damping.
fix             m1 all property/global kn peratomtypepair 2 {kn}
fix             m2 all property/global kt peratomtypepair 2 {kt}
fix             m3 all property/global gamman peratomtypepair 2 {gn}
fix             m4 all property/global gammat peratomtypepair 2 0 0 0 0
fix             m5 all property/global coefficientFriction peratomtypepair 2 {mu}

pair_style      gran model hooke/stiffness tangential history
pair_coeff      * *
timestep        {dt}

fix             gravity all gravity {g} vector 0.0 0.0 -1.0
fix             floor all {wall_model} zplane 0.0
{walls}
fix             integrate all nve/sphere
{thermo}{run})",
      fmt::arg("preamble", LiggghtsPreamble()), fmt::arg("box", box),
      fmt::arg("skin", Number(0.2 * d)),
      fmt::arg("kn", per_type_pair(mapping.pair.stiffness_n_per_m, mapping.wall.stiffness_n_per_m)),
      fmt::arg("kt",
               per_type_pair(spec.tangential_stiffness_n_per_m, spec.tangential_stiffness_n_per_m)),
      fmt::arg("gn",
               per_type_pair(mapping.pair.damping_rate_per_s, mapping.wall.damping_rate_per_s)),
      fmt::arg("mu", per_type_pair(spec.friction, spec.wall_friction)),
      fmt::arg("dt", Number(spec.time_step_s)), fmt::arg("g", Number(spec.gravity_mps2)),
      fmt::arg("wall_model", wall_model), fmt::arg("walls", walls),
      fmt::arg("thermo", ThermoCommands(deck)), fmt::arg("run", RunCommands(plan, pour, deck)));
}

// fix wall/gran's hooke/history arguments: the card law's wall coefficients (m_eff = m), the
// scene's tangential spring and wall friction: Kn Kt gamma_n gamma_t xmu dampflag.
std::string LammpsWallLaw(const PackingDeckSpec& spec, const LawMapping& mapping) {
  return fmt::format("hooke/history {} {} {} 0 {} 0", Number(mapping.wall.stiffness_n_per_m),
                     Number(spec.tangential_stiffness_n_per_m),
                     Number(mapping.wall.damping_rate_per_s), Number(spec.wall_friction));
}

// The pair style with the card law's pair coefficients (equal spheres, m_eff = m/2), the
// neighbour list (a skin of a fifth of the largest diameter) and the integrator, as 2D and 3D
// LAMMPS decks share them.
std::string LammpsPairsAndIntegration(const PackingDeckSpec& spec, const LawMapping& mapping) {
  return fmt::format(
      "# Pair contacts (equal spheres, m_eff = m/2): Kn Kt gamma_n gamma_t xmu dampflag.\n"
      "pair_style      gran/hooke/history {} {} {} 0 {} 0\n"
      "pair_coeff      * *\n"
      "neighbor        {} bin\n"
      "neigh_modify    delay 0\n"
      "\n"
      "timestep        {}\n"
      "fix             integrate all nve/sphere\n",
      Number(mapping.pair.stiffness_n_per_m), Number(spec.tangential_stiffness_n_per_m),
      Number(mapping.pair.damping_rate_per_s), Number(spec.friction),
      Number(0.2 * LargestDiameter(spec)), Number(spec.time_step_s));
}

// Disks in a box from start.data: LAMMPS needs a periodic z in 2D, and enforce2d after the
// force fixes so that no z force survives. read_data's atom_style sphere gives each particle a
// sphere's mass from its diameter and density, and nve/sphere a sphere's inertia: the same as
// bouncecal's 2D engine.
std::string Lammps2dPackingScript(const PackingDeckSpec& spec, const LawMapping& mapping,
                                  const Deck& deck) {
  const double x = spec.box_half_x_m;
  const double x0 = spec.origin_m[0], y0 = spec.origin_m[1];
  const std::string wall_law = LammpsWallLaw(spec, mapping);
  return fmt::format(
      R"(
{preamble}read_data       start.data

{pairs}fix             gravity all gravity {g} vector 0 -1 0
# Wall contacts (sphere on wall, m_eff = m).
fix             floor all wall/gran {wall} yplane {floor} {top}
fix             sides all wall/gran {wall} xplane {left} {right}
fix             plane all enforce2d

{thermo}{dump}run             {steps}
write_data      final.data
)",
      fmt::arg("preamble", LammpsPreamble(2, /*atom_map=*/false)),
      fmt::arg("pairs", LammpsPairsAndIntegration(spec, mapping)),
      fmt::arg("g", Number(spec.gravity_mps2)), fmt::arg("wall", wall_law),
      fmt::arg("floor", Number(y0)),
      fmt::arg("top", spec.closed_top ? Number(y0 + spec.container_height_m) : "NULL"),
      fmt::arg("left", Number(x0 - x)), fmt::arg("right", Number(x0 + x)),
      fmt::arg("thermo", ThermoCommands(deck)), fmt::arg("dump", DumpCommand(deck)),
      fmt::arg("steps", deck.steps));
}

// fix pour's tries per particle of a batch (its default, 50, gives up long before bouncecal's
// random placement, which tries 20000 times in a row).
constexpr int kLammpsPourAttempts = 500;

// fix pour sizes its batches by a volume fraction of its region and spaces them by the fall
// time through it (neither can be given directly): the fraction that asks for the planned batch.
struct LammpsPour {
  double volume_fraction = 0.25;
  std::int64_t per_batch = 1;
  std::int64_t every_steps = 1;
};

LammpsPour PlanLammpsPour(const PackingDeckSpec& spec, const PourPlan& plan,
                          const Regions& regions) {
  LammpsPour pour;
  const double largest_volume = std::numbers::pi * std::pow(LargestDiameter(spec), 3) / 6;
  pour.volume_fraction = std::min(1.0, (static_cast<double>(plan.per_batch) + 0.5) *
                                           largest_volume / regions.centres_volume_m3);
  pour.per_batch = std::max<std::int64_t>(
      1,
      static_cast<std::int64_t>(pour.volume_fraction * regions.centres_volume_m3 / largest_volume));
  pour.every_steps = std::max<std::int64_t>(
      1,
      std::llround(std::sqrt(2 * regions.centres_band_m / spec.gravity_mps2) / spec.time_step_s));
  return pour;
}

std::int64_t CeilDiv(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

// How the deck inserts its particles, and a warning when its pour cannot finish in the run.
void AddInsertionNotes(const PackingDeckSpec& spec, const PourPlan& plan, const LammpsPour* lammps,
                       Deck& deck) {
  const auto started = static_cast<std::int64_t>(spec.start_spheres.size());
  if (started > 0) {
    deck.notes.push_back(fmt::format(
        "Start: read_data start.data, the {} spheres bouncecal's engine places at t = 0 by the "
        "scene's seed ({}), at rest, every centre at least a radius inside the insertion region "
        "and so inside the container.",
        started, plan.count == 0 ? "all of them" : "its first pour batch"));
  }
  if (plan.count == 0) return;
  const double dt = spec.time_step_s;
  if (plan.first_step >= deck.steps) {
    deck.notes.push_back(fmt::format(
        "The other {} particles are due after the run ({} s batch interval, {} s run): they are "
        "never poured, as in bouncecal pack.",
        plan.count, Number(plan.every_steps * dt), Number(spec.duration_s)));
    return;
  }
  const std::int64_t per_batch = lammps ? lammps->per_batch : plan.per_batch;
  const std::int64_t every = lammps ? lammps->every_steps : plan.every_steps;
  const std::int64_t last_step = plan.first_step + (CeilDiv(plan.count, per_batch) - 1) * every;
  const std::string poured =
      started > 0 ? fmt::format("The other {}", plan.count) : fmt::format("All {}", plan.count);
  if (lammps) {
    deck.notes.push_back(fmt::format(
        "{} particles are poured by fix pour from t = {} s, their centres drawn a largest radius "
        "inside the scene's insertion region (region insert), as bouncecal places them: batches "
        "of up to {} (vol {:.4g}, {} tries per particle) every {} steps, fix pour's fall time "
        "through the band, so the last is due at t = {} s (later if a crowded batch falls short; "
        "thermo prints the atom count).",
        poured, Number(plan.first_step * dt), per_batch, lammps->volume_fraction,
        kLammpsPourAttempts, every, Number(last_step * dt)));
  } else {
    deck.notes.push_back(fmt::format(
        "{} particles are poured by insert/rate/region (all_in yes: whole particles inside the "
        "scene's insertion region, as bouncecal places them) from t = {} s: up to {} every {} "
        "steps, so the last batch is due at t = {} s (later if a crowded batch falls short; "
        "thermo prints the atom count).",
        poured, Number(plan.first_step * dt), per_batch, every, Number(last_step * dt)));
  }
  if (last_step >= deck.steps) {
    deck.notes.push_back(fmt::format(
        "WARNING: the deck's last batch of {} poured particles is due at t = {} s, after the "
        "scene's {} s run, so the run ends with fewer than {} particles; raise duration_s above "
        "{} s plus the settling time, or enlarge the insertion region so that batches hold more.",
        plan.count, Number(last_step * dt), Number(spec.duration_s), spec.particle_count,
        Number(last_step * dt)));
  }
}

// Spheres in a cylinder or box: read_data of the start spheres (or an empty box), then fix pour
// for the rest; the pair style carries the pair coefficients, fix wall/gran the wall's.
std::string Lammps3dPackingScript(const PackingDeckSpec& spec, const LawMapping& mapping,
                                  const PourPlan& plan, const Regions& regions,
                                  const LammpsPour& lammps_pour, const Deck& deck) {
  const std::string wall_law = LammpsWallLaw(spec, mapping);
  std::string wall_sides;
  if (spec.container == PackingContainer::kCylinder) {
    wall_sides = fmt::format("fix             side all wall/gran {} zcylinder {}\n", wall_law,
                             Number(spec.container_radius_m));
  } else {
    wall_sides = fmt::format(
        "fix             side_x all wall/gran {0} xplane {1} {2}\n"
        "fix             side_y all wall/gran {0} yplane {3} {4}\n",
        wall_law, Number(-spec.box_half_x_m), Number(spec.box_half_x_m), Number(-spec.box_half_y_m),
        Number(spec.box_half_y_m));
  }

  const std::string box = spec.start_spheres.empty() ? fmt::format(
                                                           "region          box {} units box\n"
                                                           "create_box      1 box\n",
                                                           regions.box)
                                                     : "read_data       start.data\n";
  const std::string pour = fmt::format(
      "region          insert {insert} units box\n"
      "fix             pour all pour {count} 1 {seed} region insert diam {diam} dens {rho} {rho} "
      "vol {fraction} {attempts}\n",
      fmt::arg("insert", regions.centres), fmt::arg("count", plan.count),
      fmt::arg("seed", spec.seed),
      fmt::arg("diam", spec.max_diameter_m ? fmt::format("range {} {}", Number(spec.diameter_m),
                                                         Number(*spec.max_diameter_m))
                                           : fmt::format("one {}", Number(spec.diameter_m))),
      fmt::arg("rho", Number(spec.density_kg_per_m3)),
      fmt::arg("fraction", Number(lammps_pour.volume_fraction)),
      fmt::arg("attempts", kLammpsPourAttempts));
  return fmt::format(
      R"(
{preamble}
{box}
{pairs}fix             gravity all gravity {g} vector 0 0 -1
# Wall contacts (sphere on wall, m_eff = m): the contact the drop calibration measured.
fix             floor all wall/gran {wall} zplane 0.0 NULL
{sides}
{thermo}{run})",
      fmt::arg("preamble", LammpsPreamble(3, /*atom_map=*/false)), fmt::arg("box", box),
      fmt::arg("pairs", LammpsPairsAndIntegration(spec, mapping)),
      fmt::arg("g", Number(spec.gravity_mps2)), fmt::arg("wall", wall_law),
      fmt::arg("sides", wall_sides), fmt::arg("thermo", ThermoCommands(deck)),
      fmt::arg("run", RunCommands(plan, pour, deck)));
}

// The card's law for the scene's particle: its mass at the mean diameter, at the typical first
// impact of a pour (a fall from the middle of the insertion band) or, from start positions, of a
// fall through half the container.
LawMapping MapLawForScene(const ExportMaterial& material, const PackingDeckSpec& spec,
                          Engine engine) {
  const double d = MeanDiameter(spec);
  const double mass = SphereMass(d, spec.density_kg_per_m3);
  const double fall_m = spec.start_data ? 0.5 * spec.container_height_m
                                        : 0.5 * (spec.insert_z_min_m + spec.insert_z_max_m);
  const double impact_speed = std::sqrt(2 * spec.gravity_mps2 * fall_m);
  return MapContactLaw(material.law, mass, 0.5 * d, impact_speed, engine);
}

// The shortest contact (pairs of the smallest particles) sets the stability limit.
void CheckPairStability(const PackingDeckSpec& spec, const SpringDashpot& pair) {
  const double smallest_pair_mass = 0.5 * SphereMass(spec.diameter_m, spec.density_kg_per_m3);
  const double omega_dt = std::sqrt(pair.stiffness_n_per_m / smallest_pair_mass) * spec.time_step_s;
  if (omega_dt >= 2) {
    const double pair_contact_s = ContactDurationS(pair);
    throw ConfigError(fmt::format(
        "scene time step {} s is unstable for the mapped pair contact (omega dt = {:.3g} >= 2, "
        "t_c = {:.3g} s); use a step below {:.3g} s",
        spec.time_step_s, omega_dt, pair_contact_s, pair_contact_s / 20));
  }
}

// The deck's schedule: its steps, what the step costs the restitution of a pair contact (the
// shortest contact sets the discretisation error), and how often it dumps.
Deck ScheduleDeck(const PackingDeckSpec& spec, const LawMapping& mapping) {
  Deck deck;
  deck.input_file_name = "in.pack";
  deck.time_step_s = spec.time_step_s;
  deck.duration_s = spec.duration_s;
  deck.steps = static_cast<std::int64_t>(std::ceil(spec.duration_s / spec.time_step_s));
  deck.trajectory_file_name = "final.data";
  deck.expected_restitution = mapping.restitution;
  deck.time_step_error_bound = mapping.pair.damping_rate_per_s * spec.time_step_s;
  // The deck always dumps snapshots (docs/export.md): at the scene's interval, or 20 over the run
  // (the thermo cadence) when the scene asks bouncecal pack for none. LAMMPS takes an int.
  const double every_steps = spec.snapshot_interval_s > 0
                                 ? std::round(spec.snapshot_interval_s / spec.time_step_s)
                                 : std::floor(static_cast<double>(deck.steps) / 20);
  deck.output_every_steps = static_cast<int>(
      std::clamp(every_steps, 1.0, static_cast<double>(std::numeric_limits<int>::max())));
  deck.output_interval_s = deck.output_every_steps * spec.time_step_s;
  return deck;
}

// What the mapped contact keeps and loses: the mapping's own notes, the spread of e over a
// polydisperse scene, the step's cost in accuracy, the attractive tail and the tangential law.
void AddContactNotes(const PackingDeckSpec& spec, const LawMapping& mapping, Engine engine,
                     Deck& deck) {
  deck.notes = mapping.notes;
  if (spec.max_diameter_m) {
    // One coefficient set for every size: the mass-scaled dashpot gives each its own e.
    auto wall_e = [&](double diameter) {
      SpringDashpot wall = mapping.wall;
      wall.effective_mass_kg = SphereMass(diameter, spec.density_kg_per_m3);
      return Restitution(wall);
    };
    deck.notes.push_back(fmt::format(
        "POLYDISPERSE: diameters uniform in [{}, {}] m; the law is mapped for the mean diameter "
        "{} m, so on the walls the smallest particles bounce with e = {:.4f} and the largest with "
        "{:.4f} instead of {:.4f}.",
        Number(spec.diameter_m), Number(*spec.max_diameter_m), Number(MeanDiameter(spec)),
        wall_e(spec.diameter_m), wall_e(*spec.max_diameter_m), mapping.restitution));
  }
  const double pair_contact_s = ContactDurationS(mapping.pair);
  deck.notes.push_back(fmt::format(
      "Time step {} s resolves a pair contact (t_c = {:.4g} s) in {:.1f} steps and a wall contact "
      "in {:.1f}: the restitution of single contacts may deviate by up to gamma_n dt = {:.1f} % "
      "(pairs){}.",
      Number(spec.time_step_s), pair_contact_s, pair_contact_s / spec.time_step_s,
      ContactDurationS(mapping.wall) / spec.time_step_s, 100 * deck.time_step_error_bound,
      deck.time_step_error_bound > 0.05
          ? "; with so few steps per contact e scatters from bounce to bounce (bouncecal "
            "docs/physics.md section 4: 0.47-0.58 for 0.577 at 10 us), which matters for dynamics "
            "more than for the final packing"
          : ""));
  deck.notes.push_back(deck_text::AttractiveTailNote(engine == Engine::kLammps));
  deck.notes.push_back(fmt::format(
      "Tangential: Cundall-Strack spring kt = {} N/m with Coulomb friction {} (particles) and {} "
      "(walls), no tangential damping; nve/sphere integrates rotation.",
      Number(spec.tangential_stiffness_n_per_m), Number(spec.friction),
      Number(spec.wall_friction)));
}

// Where the particles come from: the scene's start positions, or bouncecal's start spheres and
// the pour of the rest; LIGGGHTS' wall type. `lammps`: fix pour's plan, null for LIGGGHTS.
void AddStartNotes(const PackingDeckSpec& spec, const PourPlan& plan, const LammpsPour* lammps,
                   Deck& deck) {
  if (spec.start_data) {
    deck.notes.push_back(fmt::format(
        "Start: read_data start.data, the scene's own start positions, at rest{}.",
        spec.dimension == 2
            ? "; 2D: dimension 2 with enforce2d, each particle a sphere (mass and inertia) whose "
              "centre moves in the x-y plane, gravity along -y"
            : ""));
  } else {
    AddInsertionNotes(spec, plan, lammps, deck);
  }
  if (!lammps) {
    deck.notes.push_back(
        "The wall is atom type 2, so wall (1-2) and pair (1-1) contacts keep their own "
        "coefficients.");
  }
}

std::string LogName(Engine engine) { return fmt::format("log.{}", ToString(engine)); }

std::string RunCommand(const PackingDeckOptions& options, const std::string& input_file_name) {
  const std::string executable(EngineExecutable(options.engine));
  const std::string log_name = LogName(options.engine);
  return options.processes > 1
             ? fmt::format("mpirun -np {} {} -in {} -log {}", options.processes, executable,
                           input_file_name, log_name)
             : fmt::format("{} -in {} -log {}", executable, input_file_name, log_name);
}

// The comment block at the top of the input script: provenance, the particles and the run, the
// notes, the outputs and how to run it.
std::vector<std::string> HeaderLines(const ExportMaterial& material, const PackingDeckSpec& spec,
                                     const PackingDeckOptions& options, const LawMapping& mapping,
                                     const Deck& deck) {
  const bool lammps = options.engine == Engine::kLammps;
  std::vector<std::string> header = {
      fmt::format("bouncecal packing-scene deck '{}' for {} ({})", spec.name,
                  ToString(options.engine),
                  lammps ? "LAMMPS 29Sep2021 or later, GRANULAR package" : "LIGGGHTS-PUBLIC 3.x"),
      fmt::format("Written by bouncecal {} from material card: {}", Version(), material.source),
      fmt::format("Scene: {}", options.scene_source),
      fmt::format("Card's contact law: {}", mapping.source_description),
      fmt::format("Particles: {} spheres of {} m, {} kg/m^3 ({} kg{}); {} s of {} s steps "
                  "({} steps); g = {} m/s^2.",
                  spec.particle_count,
                  spec.max_diameter_m
                      ? fmt::format("{}-{}", Number(spec.diameter_m), Number(*spec.max_diameter_m))
                      : Number(MeanDiameter(spec)),
                  Number(spec.density_kg_per_m3),
                  Number(SphereMass(MeanDiameter(spec), spec.density_kg_per_m3)),
                  spec.max_diameter_m ? " at the mean diameter" : " each", Number(spec.duration_s),
                  Number(spec.time_step_s), deck.steps, Number(spec.gravity_mps2)),
      ""};
  for (const auto& note : deck.notes) header.push_back(note);
  header.push_back("");
  header.push_back(fmt::format(
      "Outputs: {} (thermo: atoms, kinetic energy), dump.pack (snapshots every {} s from t = 0: "
      "id type radius x y z vx vy vz), final.data (write_data of the final packing).",
      LogName(options.engine), Number(deck.output_interval_s)));
  header.push_back(fmt::format("Run in this folder: {}", deck.run_command));
  return header;
}

}  // namespace

Deck MakePackingDeck(const ExportMaterial& material, const PackingDeckSpec& spec,
                     const PackingDeckOptions& options) {
  Validate(spec, options);
  const LawMapping mapping = MapLawForScene(material, spec, options.engine);
  CheckPairStability(spec, mapping.pair);
  Deck deck = ScheduleDeck(spec, mapping);
  const bool lammps = options.engine == Engine::kLammps;
  const PourPlan plan = PlanPour(spec);
  const Regions regions = MakeRegions(spec);
  const LammpsPour lammps_pour = PlanLammpsPour(spec, plan, regions);
  AddContactNotes(spec, mapping, options.engine, deck);
  AddStartNotes(spec, plan, lammps ? &lammps_pour : nullptr, deck);
  deck.run_command = RunCommand(options, deck.input_file_name);

  std::string script = CommentBlock(HeaderLines(material, spec, options, mapping, deck));
  if (spec.dimension == 2) {
    script += Lammps2dPackingScript(spec, mapping, deck);
  } else if (lammps) {
    script += Lammps3dPackingScript(spec, mapping, plan, regions, lammps_pour, deck);
  } else {
    script += LiggghtsPackingScript(spec, mapping, plan, regions, deck);
  }
  // The input script first (Deck::files), then the start the scene or bouncecal's engine gives.
  deck.files.push_back({deck.input_file_name, script});
  if (spec.dimension == 2) {
    deck.files.push_back({"start.data", *spec.start_data});
  } else if (!spec.start_spheres.empty()) {
    deck.files.push_back({"start.data", StartDataFile(spec, regions, lammps)});
  }
  return deck;
}

}  // namespace bouncecal::calibrate
