#include "bouncecal/dem/scene_templates.h"

#include <algorithm>
#include <array>

namespace bouncecal::dem {
namespace {

// Steel spheres, d = 1 cm, poured into a cylinder: paper 000's set-up at a smaller count. The step
// is 0.33 of the tangential spring's stability limit for a sphere pair (2 sqrt(m / (7 k_t)) =
// 15 us) and 0.17 of the normal one, below the half that CheckTimeStep asks for.
constexpr std::string_view kCylinder3d = R"({
  "_comment": [
    "A bouncecal packing scene (docs/scenes.md), written by: bouncecal pack `template=3d-cylinder`",
    "Keys starting with '_' are comments: the reader skips them (a JSON file has no other kind).",
    "Every quantity is SI and every name carries its unit. Run: bouncecal pack scene.json `plot`",
    "Keys left out take their defaults; a missing required key or an unknown one is named in one",
    "error with every other such key."
  ],
  "format": "bouncecal-scene/1",
  "name": "cylinder_pour",
  "description": "300 steel spheres (d = 1 cm) poured into a cylinder, R = 5 cm.",
  "dimension": 3,
  "particles": {
    "_comment": [
      "count: whole number of particles (1e5 is accepted).",
      "diameter_m: one size for all; or \"diameter\": {\"distribution\": \"uniform\", \"min_m\": a,",
      "\"max_m\": b}. species: density_kg_per_m3 (1e-3..1e6) and volume_fraction (the fractions",
      "sum to 1; with one species it may be left out)."
    ],
    "count": 300,
    "diameter_m": 0.01,
    "species": [{"name": "steel", "density_kg_per_m3": 7800, "volume_fraction": 1}]
  },
  "container": {
    "_comment": [
      "cylinder (3D only): center_m is the centre of the floor, open at the top.",
      "Other types: box (min_m, max_m, closed_top) and plane (point_m, normal)."
    ],
    "type": "cylinder",
    "center_m": [0, 0, 0],
    "radius_m": 0.05,
    "height_m": 0.2
  },
  "insertion": {
    "_comment": [
      "pour: every batch_interval_s, as many waiting particles as fit are placed at random,",
      "without overlap, inside region; random: all at once at t = 0; file: start positions from",
      "\"path\" (CSV or LAMMPS data file). The region lies inside the container's footprint and",
      "may rise above an open top. seed fixes the placement; initial_velocity_mps defaults to 0."
    ],
    "type": "pour",
    "region": {"type": "cylinder", "center_m": [0, 0], "radius_m": 0.045, "z_min_m": 0.1,
               "z_max_m": 0.2},
    "batch_interval_s": 0.1,
    "seed": 1
  },
  "material": {
    "_comment": [
      "contact_law: any law of bouncecal simulate drop `help` with its parameters; or, instead,",
      "\"material_card\": \"steel.json\", a card written by bouncecal calibrate `card` (its law is",
      "used; a relative path is read from this file's folder). The law object takes no comments.",
      "tangential_stiffness_n_per_m, friction, wall_friction (default: friction): the",
      "Cundall-Strack spring and its Coulomb cap. Van der Waals (hamaker_j, vdw_min_gap_m,",
      "vdw_cutoff_gap_m) and local_damping act only when switched on in physics."
    ],
    "contact_law": {"law": "walton-braun",
                    "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
    "tangential_stiffness_n_per_m": 1e7,
    "friction": 0.3,
    "wall_friction": 0.3
  },
  "physics": {
    "_comment": "Which forces act; rotation needs tangential. Defaults shown except rotation's.",
    "tangential": true,
    "rotation": true,
    "van_der_waals": false,
    "local_damping": false,
    "stop_at_first_contact": false
  },
  "_comment_time_step_s": [
    "time_step_s is checked against the stability limits of the stiffest contacts before the",
    "run: beyond the normal limit the run is refused, beyond half of either limit it warns.",
    "duration_s is simulated seconds (`duration_s` overrides it); gravity points along -z."
  ],
  "time_step_s": 5e-6,
  "duration_s": 1,
  "gravity_mps2": 9.81,
  "measurement": {
    "_comment": [
      "band_m: the heights [low, high] over which the packing density is measured.",
      "profile_bin_m: slab height of the density profile (default d/4); history_interval_s:",
      "density and kinetic energy versus time; contact_tolerance: touching when the centre",
      "distance is below this times the sum of the radii."
    ],
    "band_m": [0.005, 0.025],
    "profile_bin_m": 0.0025,
    "contact_tolerance": 1.0005,
    "history_interval_s": 0.01
  },
  "outputs": {
    "_comment": "directory: relative to this file (-o overrides); snapshot_interval_s: 0 for none.",
    "directory": "cylinder_pour_out",
    "snapshot_interval_s": 0
  }
}
)";

// Frictional disks settling in a closed 2D box: paper 004's set-up without van der Waals. The step
// is 0.21 of the tangential spring's limit for a pair and 0.11 of the normal one.
constexpr std::string_view kBox2d = R"({
  "_comment": [
    "A bouncecal packing scene (docs/scenes.md), written by: bouncecal pack `template=2d-box`",
    "Keys starting with '_' are comments: the reader skips them (a JSON file has no other kind).",
    "Every quantity is SI and every name carries its unit. Run: bouncecal pack scene.json `plot`",
    "In 2D the particles are spheres whose centres move in the x-y plane; gravity points along -y."
  ],
  "format": "bouncecal-scene/1",
  "name": "disks_in_a_box",
  "description": "240 steel disks (d = 100 um) settling from a random start in a 2 mm box.",
  "dimension": 2,
  "particles": {
    "_comment": "count, diameter_m (or a uniform \"diameter\" distribution) and the species.",
    "count": 240,
    "diameter_m": 0.0001,
    "species": [{"name": "steel", "density_kg_per_m3": 7860, "volume_fraction": 1}]
  },
  "container": {
    "_comment": "box: min_m and max_m corners [x, y]; closed_top adds a lid (default false).",
    "type": "box",
    "min_m": [0, 0],
    "max_m": [0.002, 0.002],
    "closed_top": true
  },
  "insertion": {
    "_comment": [
      "random: every particle at t = 0, placed at random without overlap inside region (random",
      "sequential addition; too few fit in max_attempts tries: the run is refused). seed fixes it."
    ],
    "type": "random",
    "region": {"type": "box", "min_m": [0, 0], "max_m": [0.002, 0.002]},
    "max_attempts": 900000,
    "seed": 1
  },
  "material": {
    "_comment": [
      "linear-dashpot: a spring and a viscous dashpot (damping_ratio 0.1: restitution 0.73).",
      "Or \"material_card\": \"card.json\" from bouncecal calibrate `card` instead of contact_law.",
      "The law object takes no comments."
    ],
    "contact_law": {"law": "linear-dashpot",
                    "parameters": {"stiffness_n_per_m": 100, "damping_ratio": 0.1}},
    "tangential_stiffness_n_per_m": 100,
    "friction": 0.364,
    "wall_friction": 0.364
  },
  "physics": {
    "_comment": "van_der_waals adds the Hamaker attraction (material.hamaker_j, vdw_*_gap_m).",
    "tangential": true,
    "rotation": true,
    "van_der_waals": false,
    "local_damping": false,
    "stop_at_first_contact": false
  },
  "time_step_s": 1e-6,
  "duration_s": 0.2,
  "gravity_mps2": 9.81,
  "measurement": {
    "_comment": "window: the rectangle [x, y] corners over which the area fraction is measured.",
    "window": {"min_m": [0.0002, 0.0002], "max_m": [0.0018, 0.0011]},
    "profile_bin_m": 2.5e-05,
    "history_interval_s": 0.0025
  },
  "outputs": {
    "_comment": "directory: relative to this file (-o overrides); snapshot_interval_s: 0 for none.",
    "directory": "disks_in_a_box_out",
    "snapshot_interval_s": 0
  }
}
)";

constexpr std::array<SceneTemplate, 2> kTemplates{{
    {"3d-cylinder", "steel spheres poured into a cylinder (paper 000's set-up, 300 spheres)",
     kCylinder3d},
    {"2d-box", "frictional disks settling in a closed box (paper 004's set-up)", kBox2d},
}};

}  // namespace

std::span<const SceneTemplate> SceneTemplates() { return kTemplates; }

std::optional<SceneTemplate> FindSceneTemplate(std::string_view name) {
  const auto it = std::find_if(kTemplates.begin(), kTemplates.end(),
                               [&](const SceneTemplate& t) { return t.name == name; });
  if (it == kTemplates.end()) return std::nullopt;
  return *it;
}

}  // namespace bouncecal::dem
