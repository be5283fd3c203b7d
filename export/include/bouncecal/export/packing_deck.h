#ifndef BOUNCECAL_EXPORT_PACKING_DECK_H_
#define BOUNCECAL_EXPORT_PACKING_DECK_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/export/drop_deck.h"
#include "bouncecal/export/export_material.h"

namespace bouncecal::calibrate {

// What an exported packing deck needs of a 3D pour scene, engine-neutral and SI. The defaults
// are the paper's scene (docs/physics.md section 3): 2000 spheres of 1 cm poured from 20 cm into
// a cylinder of R = 10 cm, k_s = 1e7 N/m, mu = 0.3, dt = 10 us, 3 s. PackingDeckSpecFromScene
// (scene_packing.h) converts a scene file's dem::Scene to it.
enum class PackingContainer {
  kCylinder,  // floor z = 0 and the inside of a vertical cylinder about the z axis
  kBox,       // floor z = 0 and four side walls at x = +-half_x, y = +-half_y
};

// One sphere at rest at the start of a 3D deck, relative to the container's floor centre.
struct StartSphere {
  double x_m = 0;
  double y_m = 0;
  double z_m = 0;
  double diameter_m = 0;
};

struct PackingDeckSpec {
  std::string name = "packing";
  std::int64_t particle_count = 2000;
  double diameter_m = 0.01;
  // When set: diameters uniform in [diameter_m, max_diameter_m]. The law is then mapped for the
  // mean diameter's mass, and the header states the wall restitution of the smallest and the
  // largest particle (a mass-scaled dashpot gives each size its own e).
  std::optional<double> max_diameter_m;
  double density_kg_per_m3 = 7800;
  PackingContainer container = PackingContainer::kCylinder;
  double container_radius_m = 0.1;  // kCylinder
  double box_half_x_m = 0.1;        // kBox
  double box_half_y_m = 0.1;
  double container_height_m = 0.2;  // walls (and the simulation box) reach this high at least
  // Particles are poured from this height band, over the container's section less one diameter
  // unless given; batches follow as earlier ones fall out of the band (LAMMPS fix pour decides
  // the batch size and interval itself; LIGGGHTS takes batch_interval_s, default: the time to
  // fall through the band).
  double insert_z_min_m = 0.15;
  double insert_z_max_m = 0.25;
  std::optional<double> insert_radius_m;  // kCylinder
  std::optional<double> insert_half_x_m;  // kBox
  std::optional<double> insert_half_y_m;
  std::optional<double> batch_interval_s;
  double tangential_stiffness_n_per_m = 1e7;
  double friction = 0.3;       // particle-particle Coulomb coefficient
  double wall_friction = 0.3;  // particle-wall
  double time_step_s = 1e-5;
  double duration_s = 3;
  double gravity_mps2 = 9.81;
  std::uint32_t seed = 12345;  // positive, for fix pour
  // dump.pack every this long; 0 (a scene that asks bouncecal pack for no dumps): 20 snapshots
  // over the run. The deck always dumps, from t = 0.
  double snapshot_interval_s = 0.1;
  // 2: spheres whose centres move in the x-y plane (LAMMPS `dimension 2`, `enforce2d`, with a
  // sphere's mass and inertia, as bouncecal's 2D scenes), gravity along -y, in a box whose floor
  // is y = 0 and whose side walls are x = +-box_half_x_m; container_height_m is the box's height
  // along y. LAMMPS only, and only from start_data.
  int dimension = 3;
  bool closed_top = false;  // 2D: a wall at y = container_height_m too
  // When set, the deck starts from these particles (a LAMMPS data file, atom_style sphere, written
  // beside the input as start.data and read with read_data) instead of pouring; the insertion
  // fields are then unused. Its coordinates are the scene's: the container's floor centre sits at
  // origin_m (x, y, z; in 2D x and y).
  std::optional<std::string> start_data;
  double origin_m[3] = {0, 0, 0};
  // 3D: the spheres bouncecal's own engine places at t = 0 (its random placement by the scene's
  // seed: all of a random start, the first batch of a pour), written beside the input as
  // start.data and read with read_data, so that the deck starts where `bouncecal pack` does.
  // When fewer than particle_count, the rest are poured from the insertion band, the first of
  // them batch_interval_s later (the scene's schedule); empty: all are poured from t = 0.
  std::vector<StartSphere> start_spheres;
};

struct PackingDeckOptions {
  Engine engine = Engine::kLammps;
  int processes = 2;  // MPI ranks in the printed run command; 1: a serial command
  std::string scene_source = "(scene given in memory)";
};

// The packing scene deck. LAMMPS: gran/hooke/history between particles with the card law's pair
// coefficients (m_eff = m/2), fix wall/gran with its wall coefficients (m_eff = m), insertion by
// read_data of the start spheres, then fix pour for any rest. LIGGGHTS: model hooke/stiffness
// with per-type-pair coefficients (the walls are atom type 2), read_data of the start spheres,
// then insert/rate/region in batches for any rest. Poured centres keep a largest radius inside
// the insertion region, as bouncecal's engine places them. Both: Cundall-Strack tangential history
// with Coulomb friction, nve/sphere with rotation, thermo (atoms, kinetic energies), dump
// snapshots (dump.pack), write_data of the final packing (final.data). A 2D spec (LAMMPS only)
// reads its start.data and runs with enforce2d between wall/gran planes. The header states the
// mapping and what the scene's time step costs in accuracy. Throws ConfigError for a spec outside
// its ranges (naming the field) or a step that is unstable for the mapped pair contact.
Deck MakePackingDeck(const ExportMaterial& material, const PackingDeckSpec& spec,
                     const PackingDeckOptions& options);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_PACKING_DECK_H_
