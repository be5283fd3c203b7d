#include "scene/particle_file.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <string>

#include "bouncecal/error.h"
#include "scene/overlap_checks.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene {

using particle_file::FileParticle;
using particle_file::Position;
using particle_file::RefuseCount;
using particle_file::Where;

namespace {

std::vector<FileParticle> ReadFileParticles(const std::filesystem::path& path, int dimension) {
  // An ifstream opens a directory without complaint and then fails on the first read.
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(path.string() +
                     ": is a directory, not a particle file; give a .csv or LAMMPS data file in "
                     "insertion.path");
  }
  std::ifstream in(path);
  if (!in) {
    throw InputError(path.string() + ": cannot open the particle file; check insertion.path");
  }
  const auto ext = path.extension().string();
  auto particles = ext == ".csv" || ext == ".CSV"
                       ? particle_file::ReadCsv(in, path, dimension)
                       : particle_file::ReadLammpsData(in, path, dimension);
  if (particles.empty()) {
    throw InputError(path.string() +
                     ": holds no particles; a start-positions file needs at least one");
  }
  RefuseCount(path, static_cast<double>(particles.size()), dimension);
  RefuseHeavyOverlaps(particles, path, dimension);
  return particles;
}

std::vector<NewParticle> Particles(const std::vector<FileParticle>& read) {
  std::vector<NewParticle> out;
  out.reserve(read.size());
  for (const auto& f : read) out.push_back(f.particle);
  return out;
}

// Why a particle of a start file lies outside the container, or nullopt. A settled pack presses
// its particles into the walls a little, so one may overlap a wall by up to half its radius; a
// centre further out starts behind a wall that acts from one side only. There is no limit above
// an open container (a cylinder, a box without lid): a file may hold particles about to fall in.
std::optional<std::string> OutsideContainer(const ContainerSpec& c, int dimension,
                                            const NewParticle& p) {
  static constexpr char kAxis[] = "xyz";
  const Vec3& x = p.position_m;
  const double half = 0.5 * p.radius_m;
  const int up = dimension - 1;
  switch (c.kind) {
    case ContainerKind::kPlane: {
      double norm = 0;
      for (int d = 0; d < dimension; ++d) norm += c.normal[d] * c.normal[d];
      norm = std::sqrt(norm);
      double wall = 0;  // the plane's and the centre's positions along the unit normal
      double centre = 0;
      for (int d = 0; d < dimension; ++d) {
        wall += c.point_m[d] * c.normal[d] / norm;
        centre += x[d] * c.normal[d] / norm;
      }
      if (!AtMostUpToRounding(wall + half, centre)) {
        return fmt::format("its centre is {:.9g} m from the container's plane", centre - wall);
      }
      return std::nullopt;
    }
    case ContainerKind::kCylinder: {
      const double rho = std::hypot(x[0] - c.center_m[0], x[1] - c.center_m[1]);
      if (!AtMostUpToRounding(rho + half, c.radius_m)) {
        return fmt::format(
            "its centre is {:.9g} m from the axis of the cylinder at ({:.9g}, {:.9g}), whose "
            "radius is {:.9g} m",
            rho, c.center_m[0], c.center_m[1], c.radius_m);
      }
      if (!AtMostUpToRounding(c.center_m[2] + half, x[2])) {
        return fmt::format("its centre is at z = {:.9g} m, the floor at z = {:.9g} m", x[2],
                           c.center_m[2]);
      }
      return std::nullopt;
    }
    case ContainerKind::kBox:
      for (int d = 0; d < dimension; ++d) {
        if (!AtMostUpToRounding(c.min_m[d] + half, x[d])) {
          return fmt::format("its centre is at {0} = {1:.9g} m, the {2} at {0} = {3:.9g} m",
                             kAxis[d], x[d], d == up ? "floor" : "side wall", c.min_m[d]);
        }
        if ((d != up || c.closed_top) && !AtMostUpToRounding(x[d] + half, c.max_m[d])) {
          return fmt::format("its centre is at {0} = {1:.9g} m, the {2} at {0} = {3:.9g} m",
                             kAxis[d], x[d], d == up ? "lid" : "side wall", c.max_m[d]);
        }
      }
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

std::vector<NewParticle> ReadParticleFile(const std::filesystem::path& path, int dimension) {
  return Particles(ReadFileParticles(path, dimension));
}

std::vector<NewParticle> ReadParticleFile(const Scene& scene) {
  const auto& path = scene.insertion.file;
  const auto read = ReadFileParticles(path, scene.dimension);
  const std::size_t species = scene.particles.species.size();
  for (const auto& f : read) {
    const NewParticle& p = f.particle;
    if (static_cast<std::size_t>(p.species) >= species) {
      throw InputError(fmt::format(
          "{}: names species {} but the scene {} defines {} (species are 0-based); fix the "
          "particle file or add species",
          Where(path, f.line), p.species, scene.source.string(), species));
    }
    if (const auto reason = OutsideContainer(scene.container, scene.dimension, p)) {
      throw InputError(fmt::format(
          "{}: particle at {} lies outside the container ({}); a particle may overlap a wall by "
          "at most half its radius ({:.9g} m): move it inside or fix the container",
          Where(path, f.line), Position(p.position_m, scene.dimension), *reason, 0.5 * p.radius_m));
    }
  }
  if (static_cast<std::int64_t>(read.size()) != scene.particles.count) {
    throw InputError(fmt::format(
        "{}: particles.count: {} particles, but {} holds {}; make the count and the file agree",
        scene.source.empty() ? std::string("scene") : scene.source.string(), scene.particles.count,
        path.string(), read.size()));
  }
  return Particles(read);
}

}  // namespace bouncecal::dem::scene
