#ifndef BOUNCECAL_DEM_SCENE_H_
#define BOUNCECAL_DEM_SCENE_H_

#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::dem {

// A packing scene as read from a scene file (JSON, documented in docs/scenes.md). Everything is
// SI. Vectors always hold three components; 2D scenes use (x, y) and leave z at 0, gravity then
// acts along -y instead of -z.
using Vec3 = std::array<double, 3>;

struct Species {
  std::string name;
  double density_kg_per_m3 = 7800;
  double volume_fraction = 1;  // fractions of all species sum to 1
};

enum class DiameterDistributionKind { kConstant, kUniform };

struct DiameterDistribution {
  DiameterDistributionKind kind = DiameterDistributionKind::kConstant;
  double diameter_m = 0.01;      // kConstant
  double min_diameter_m = 0.01;  // kUniform: uniform in [min, max]
  double max_diameter_m = 0.01;
  double MaxDiameterM() const;
  double MeanVolumeM3(int dimension) const;  // mean sphere volume (3D) or disk area (2D)
};

struct ParticlesSpec {
  std::int64_t count = 0;
  DiameterDistribution diameter;
  std::vector<Species> species;
};

// The container the particles pack in. Walls act with the scene's contact law on one side only.
enum class ContainerKind {
  kPlane,     // one infinite plane (a floor)
  kCylinder,  // floor at center_m.z plus the inner side of a vertical cylinder (3D only)
  kBox,       // axis-aligned box: floor and side walls, a lid when closed_top (3D or 2D)
};

struct ContainerSpec {
  ContainerKind kind = ContainerKind::kCylinder;
  Vec3 center_m{0, 0, 0};  // cylinder: axis through (x, y), floor at z
  double radius_m = 0.1;
  double height_m = 0.2;  // cylinder side wall ends at floor + height
  Vec3 min_m{0, 0, 0};    // box corners
  Vec3 max_m{0, 0, 0};
  bool closed_top = false;  // box lid
  Vec3 point_m{0, 0, 0};    // plane: a point on it and its normal into the particles
  Vec3 normal{0, 0, 1};
};

enum class RegionKind { kBox, kCylinder };

// Where particles are placed: an axis-aligned box, or a vertical cylinder (3D).
struct RegionSpec {
  RegionKind kind = RegionKind::kBox;
  Vec3 min_m{0, 0, 0};  // box
  Vec3 max_m{0, 0, 0};
  Vec3 center_m{0, 0, 0};  // cylinder: axis through (x, y)
  double radius_m = 0;
  double z_min_m = 0;
  double z_max_m = 0;
};

enum class InsertionKind {
  kRandom,  // every particle at t = 0 at a random non-overlapping place in the region
  kPour,    // batches placed in the region every batch_interval_s, wherever they fit, until all
            // particles are in: a funnel/hopper pour without modelling the funnel walls
  kFile,    // positions (and diameters) read from a CSV or LAMMPS data file
};

// One particle of a start-positions file (insertion type "file"), as SceneFromJson read it.
struct StartParticle {
  Vec3 position_m{0, 0, 0};
  double radius_m = 0;
  std::int32_t species = 0;
};

struct InsertionSpec {
  InsertionKind kind = InsertionKind::kRandom;
  RegionSpec region;
  std::uint64_t seed = 1;
  std::int64_t max_attempts = 10'000'000;  // random placements tried per batch before giving up
  Vec3 initial_velocity_mps{0, 0, 0};
  double batch_interval_s = 0.1;  // kPour
  std::filesystem::path file;     // kFile: *.csv (x_m,y_m[,z_m],diameter_m[,species]) or LAMMPS
  // kFile: the particles of `file`, read and checked once by SceneFromJson, so that the run
  // uses what was checked and the file is read only once (it may be large, or a pipe). A Scene
  // built in code may leave this empty; RunPacking then reads `file`.
  std::vector<StartParticle> start_particles;
};

// Which forces Cundall's local damping reduces (docs/scenes.md, material.local_damping_scope).
enum class LocalDampingScope {
  // The whole unbalanced force, gravity included (Itasca PFC's form): a particle in free fall
  // accelerates at (1 - alpha) g.
  kUnbalancedForce,
  // Only the forces from other bodies (contacts, walls, van der Waals); gravity acts undamped, so
  // free flight is ballistic and only contacts lose energy to the damping.
  kContactForces,
};

struct MaterialSpec {
  ContactLawConfig law;                 // normal law, particle-particle and particle-wall
  std::filesystem::path material_card;  // empty when the law was given inline
  double tangential_stiffness_n_per_m = 1e7;
  double friction = 0.3;           // particle-particle Coulomb coefficient
  double wall_friction = 0.3;      // particle-wall Coulomb coefficient
  double hamaker_j = 21.1e-20;     // van der Waals: steel (paper 004)
  double vdw_min_gap_m = 4e-10;    // the gap the 1/h^2 force is evaluated at when closer
  double vdw_cutoff_gap_m = 1e-6;  // no force beyond this surface gap
  double local_damping = 0.7;      // Cundall's alpha in [0, 1)
  LocalDampingScope local_damping_scope = LocalDampingScope::kUnbalancedForce;
};

// The physics the force loop is instantiated for ("model only what a scene requires").
struct PhysicsSpec {
  bool tangential = true;      // Cundall-Strack spring with Coulomb cap, per-contact history
  bool rotation = true;        // integrate angular velocity (needs tangential to do anything)
  bool van_der_waals = false;  // Hamaker attraction between particles
  bool local_damping = false;  // Cundall local non-viscous damping
  // Paper 004: a particle's velocity is set to zero at its first collision (once per particle).
  bool stop_at_first_contact = false;
};

struct MeasurementSpec {
  // 3D: packing density over the container cross-section between these heights.
  double band_min_m = 0;
  double band_max_m = 0;
  // 2D: area fraction inside this window (x, y).
  Vec3 window_min_m{0, 0, 0};
  Vec3 window_max_m{0, 0, 0};
  double profile_bin_m = 0;           // density profile bin height; 0: a quarter diameter
  double contact_tolerance = 1.0005;  // two particles touch when |r_ij| < tolerance (R_i + R_j)
  double history_interval_s = 0.01;   // density and kinetic energy versus time
};

struct OutputSpec {
  std::filesystem::path directory;  // relative paths resolve against the scene file's folder
  double snapshot_interval_s = 0;   // LAMMPS dump text snapshots; 0: none
};

struct Scene {
  std::filesystem::path source;  // the file it came from (for messages), may be empty
  std::string name;
  int dimension = 3;
  ParticlesSpec particles;
  ContainerSpec container;
  InsertionSpec insertion;
  MaterialSpec material;
  PhysicsSpec physics;
  double time_step_s = 1e-5;
  // Why time_step_s stays above half a stability limit (e.g. the paper's own step): the run
  // then prints that choice as a note with this reason instead of warning about it. Empty: warn.
  std::string time_step_reason;
  double duration_s = 3;
  double gravity_mps2 = 9.81;
  MeasurementSpec measurement;
  OutputSpec outputs;
};

// Largest particle count a scene may ask for before it is refused with the memory it would need.
inline constexpr std::int64_t kMaxSceneParticles = 20'000'000;
// Bytes the engine needs per particle (state, neighbour lists, contact history), for the check.
std::int64_t EstimatedBytesPerParticle(int dimension);
// Why `count` particles cannot be simulated here ("N particles would need about X GB of memory
// (this machine has Y GB, the limit is Z particles)"), or nullopt when they can. A double, so
// absurd counts (1e12, 2^64) are judged by the memory they need, not by an integer range.
std::optional<std::string> ParticleCountProblem(double count, int dimension);

// Reads a scene file. Throws InputError (one line naming the file and the key) when the file is
// missing, a directory or not JSON, for unknown keys, missing fields, wrong types, values outside
// their range and an insertion region outside the container. A start-positions file (insertion
// type "file") is read and checked too (docs/scenes.md), naming its file and line.
Scene LoadScene(const std::filesystem::path& path);
// The same from parsed JSON; `source` names the file in messages and anchors relative paths.
Scene SceneFromJson(const nlohmann::json& root, const std::filesystem::path& source);

std::string_view ToString(ContainerKind kind);
std::string_view ToString(InsertionKind kind);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_SCENE_H_
