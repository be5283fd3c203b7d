#include "bouncecal/export/scene_packing.h"

#include <fmt/core.h>

#include <cmath>
#include <sstream>

#include "bouncecal/dem/packing.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {

PackingDeckSpec PackingDeckSpecFromScene(const dem::Scene& scene) {
  const std::string file = scene.source.empty() ? "scene" : scene.source.string();
  auto refuse = [&](std::string_view key, std::string_view why) {
    throw ConfigError(fmt::format("{}: {}: {}", file, key, why));
  };
  if (scene.dimension == 2 && scene.container.kind != dem::ContainerKind::kBox) {
    refuse("container.type", "2D scenes are exported in a box only");
  }
  if (scene.dimension == 2 && scene.insertion.kind == dem::InsertionKind::kPour) {
    refuse("insertion.type",
           "2D decks start from the scene's start positions; use random or file insertion");
  }
  if (scene.particles.species.size() != 1) {
    refuse("particles.species", "exported decks take one species; split the scene or export each");
  }
  if (scene.physics.van_der_waals) {
    refuse("physics.van_der_waals",
           "the Hamaker attraction has no counterpart in gran/hooke or "
           "hooke/stiffness; turn it off to export");
  }
  if (scene.physics.local_damping) {
    refuse("physics.local_damping", "Cundall's local damping has no counterpart in either engine");
  }
  if (scene.physics.stop_at_first_contact) {
    refuse("physics.stop_at_first_contact",
           "zeroing velocities at the first collision has no counterpart in either engine");
  }
  if (scene.dimension == 3 && scene.insertion.kind == dem::InsertionKind::kFile) {
    refuse("insertion.type", "file insertion is exported for 2D scenes only so far");
  }
  const auto& velocity = scene.insertion.initial_velocity_mps;
  if (velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0) {
    refuse("insertion.initial_velocity_mps", "only insertion from rest is exported");
  }

  PackingDeckSpec spec;
  spec.name = scene.name;
  spec.particle_count = scene.particles.count;
  if (scene.particles.diameter.kind == dem::DiameterDistributionKind::kUniform) {
    spec.diameter_m = scene.particles.diameter.min_diameter_m;
    spec.max_diameter_m = scene.particles.diameter.max_diameter_m;
  } else {
    spec.diameter_m = scene.particles.diameter.diameter_m;
  }
  spec.density_kg_per_m3 = scene.particles.species.front().density_kg_per_m3;
  dem::Vec3 origin{0, 0, 0};
  switch (scene.container.kind) {
    case dem::ContainerKind::kCylinder:
      spec.container = PackingContainer::kCylinder;
      origin = scene.container.center_m;
      spec.container_radius_m = scene.container.radius_m;
      spec.container_height_m = scene.container.height_m;
      break;
    case dem::ContainerKind::kBox:
      if (scene.dimension == 2) {
        spec.container = PackingContainer::kBox;
        origin = {0.5 * (scene.container.min_m[0] + scene.container.max_m[0]),
                  scene.container.min_m[1], 0};
        spec.box_half_x_m = 0.5 * (scene.container.max_m[0] - scene.container.min_m[0]);
        spec.box_half_y_m = spec.box_half_x_m;  // no y walls in 2D; kept valid for the checks
        spec.container_height_m = scene.container.max_m[1] - scene.container.min_m[1];
        spec.closed_top = scene.container.closed_top;
        break;
      }
      if (scene.container.closed_top) refuse("container.closed_top", "a lid is not exported");
      spec.container = PackingContainer::kBox;
      origin = {0.5 * (scene.container.min_m[0] + scene.container.max_m[0]),
                0.5 * (scene.container.min_m[1] + scene.container.max_m[1]),
                scene.container.min_m[2]};
      spec.box_half_x_m = 0.5 * (scene.container.max_m[0] - scene.container.min_m[0]);
      spec.box_half_y_m = 0.5 * (scene.container.max_m[1] - scene.container.min_m[1]);
      spec.container_height_m = scene.container.max_m[2] - scene.container.min_m[2];
      break;
    case dem::ContainerKind::kPlane:
      refuse("container.type", "a lone plane is not exported; use a cylinder or a box");
  }

  const auto& region = scene.insertion.region;
  if (scene.dimension == 2) {
    // The start the scene itself would run from (random placement by its seed, or its start
    // file), measured at t = 0 as `bouncecal pack --duration 0` does, in the scene's coordinates.
    spec.dimension = 2;
    for (int d = 0; d < 3; ++d) spec.origin_m[d] = origin[d];
    dem::PackOptions start_only;
    start_only.duration_s = 0;
    const dem::PackSummary start = dem::RunPacking(scene, start_only);
    std::ostringstream data;
    dem::WriteLammpsData(data, start.final_state, scene);
    spec.start_data = data.str();
  } else if (region.kind == dem::RegionKind::kCylinder) {
    if (spec.container != PackingContainer::kCylinder ||
        std::hypot(region.center_m[0] - origin[0], region.center_m[1] - origin[1]) > 1e-12) {
      refuse("insertion.region", "a cylindrical region must share the cylinder's axis");
    }
    spec.insert_radius_m = region.radius_m;
    spec.insert_z_min_m = region.z_min_m - origin[2];
    spec.insert_z_max_m = region.z_max_m - origin[2];
  } else {
    const double half_x = 0.5 * (region.max_m[0] - region.min_m[0]);
    const double half_y = 0.5 * (region.max_m[1] - region.min_m[1]);
    if (std::abs(0.5 * (region.max_m[0] + region.min_m[0]) - origin[0]) > 1e-12 ||
        std::abs(0.5 * (region.max_m[1] + region.min_m[1]) - origin[1]) > 1e-12) {
      refuse("insertion.region", "a box region must be centred over the container");
    }
    if (spec.container == PackingContainer::kCylinder) {
      spec.insert_radius_m = std::min(half_x, half_y);  // the largest circle inside the box
    } else {
      spec.insert_half_x_m = half_x;
      spec.insert_half_y_m = half_y;
    }
    spec.insert_z_min_m = region.min_m[2] - origin[2];
    spec.insert_z_max_m = region.max_m[2] - origin[2];
  }
  if (scene.dimension == 3) {
    // The spheres bouncecal's engine places at t = 0 (all of a random start, the first batch of
    // a pour), so that the deck starts where `bouncecal pack` does; any rest is poured.
    dem::PackOptions start_only;
    start_only.duration_s = 0;
    const dem::ParticleSnapshot start = dem::RunPacking(scene, start_only).final_state;
    spec.start_spheres.reserve(start.size());
    for (std::size_t i = 0; i < start.size(); ++i) {
      const auto& x = start.position_m[i];
      spec.start_spheres.push_back(
          {x[0] - origin[0], x[1] - origin[1], x[2] - origin[2], 2 * start.radius_m[i]});
    }
  }
  if (scene.insertion.kind == dem::InsertionKind::kPour) {
    spec.batch_interval_s = scene.insertion.batch_interval_s;
  }
  spec.seed = static_cast<std::uint32_t>(scene.insertion.seed % 2'000'000'000 + 1);

  spec.tangential_stiffness_n_per_m =
      scene.physics.tangential ? scene.material.tangential_stiffness_n_per_m : 0;
  spec.friction = scene.physics.tangential ? scene.material.friction : 0;
  spec.wall_friction = scene.physics.tangential ? scene.material.wall_friction : 0;
  spec.time_step_s = scene.time_step_s;
  spec.duration_s = scene.duration_s;
  spec.gravity_mps2 = scene.gravity_mps2;
  spec.snapshot_interval_s = scene.outputs.snapshot_interval_s;
  return spec;
}

}  // namespace bouncecal::calibrate
