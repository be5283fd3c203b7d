#include "scene/insertion.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>

#include "bouncecal/error.h"

namespace bouncecal::dem::scene {

std::uint64_t SceneRandom::Next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::vector<NewParticle> DrawParticles(const Scene& scene, SceneRandom& random) {
  const auto& p = scene.particles;
  const auto count = p.count;
  std::vector<std::int32_t> species;
  species.reserve(static_cast<std::size_t>(count));
  // Largest-remainder apportionment of the count over the species' fractions.
  std::vector<std::int64_t> share(p.species.size());
  std::vector<std::pair<double, std::size_t>> remainder;
  std::int64_t given = 0;
  for (std::size_t s = 0; s < p.species.size(); ++s) {
    const double exact = p.species[s].volume_fraction * static_cast<double>(count);
    share[s] = static_cast<std::int64_t>(std::floor(exact));
    given += share[s];
    remainder.emplace_back(-(exact - std::floor(exact)), s);
  }
  std::sort(remainder.begin(), remainder.end());
  for (std::size_t k = 0; given < count; k = (k + 1) % remainder.size(), ++given) {
    ++share[remainder[k].second];
  }
  for (std::size_t s = 0; s < share.size(); ++s) {
    species.insert(species.end(), static_cast<std::size_t>(share[s]), static_cast<std::int32_t>(s));
  }
  for (std::size_t i = species.size(); i > 1; --i) {  // Fisher-Yates
    std::swap(species[i - 1], species[static_cast<std::size_t>(random.Next() % i)]);
  }
  std::vector<NewParticle> particles(static_cast<std::size_t>(count));
  const auto& dist = p.diameter;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double diameter = dist.kind == DiameterDistributionKind::kConstant
                                ? dist.diameter_m
                                : random.Uniform(dist.min_diameter_m, dist.max_diameter_m);
    particles[i].radius_m = 0.5 * diameter;
    particles[i].species = species[i];
  }
  return particles;
}

namespace {

// Hash grid over the region for overlap checks during placement.
class PlacementGrid {
 public:
  PlacementGrid(double cell_m, int dimension) : inv_cell_(1.0 / cell_m), dimension_(dimension) {}

  void Add(const NewParticle& p) {
    cells_[Key(Cell(p.position_m, 0), Cell(p.position_m, 1), Cell(p.position_m, 2))].push_back(
        particles_.size());
    particles_.push_back(p);
  }

  bool Overlaps(const Vec3& x, double r) const {
    const std::int64_t cx = Cell(x, 0);
    const std::int64_t cy = Cell(x, 1);
    const std::int64_t cz = Cell(x, 2);
    const int dz = dimension_ == 3 ? 1 : 0;
    for (std::int64_t a = cx - 1; a <= cx + 1; ++a) {
      for (std::int64_t b = cy - 1; b <= cy + 1; ++b) {
        for (std::int64_t c = cz - dz; c <= cz + dz; ++c) {
          const auto it = cells_.find(Key(a, b, c));
          if (it == cells_.end()) continue;
          for (std::size_t k : it->second) {
            const NewParticle& o = particles_[k];
            double dist2 = 0;
            for (int d = 0; d < 3; ++d)
              dist2 += (x[d] - o.position_m[d]) * (x[d] - o.position_m[d]);
            const double touch = r + o.radius_m;
            if (dist2 < touch * touch) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  std::int64_t Cell(const Vec3& x, int d) const {
    return static_cast<std::int64_t>(std::floor(x[d] * inv_cell_));
  }
  static std::uint64_t Key(std::int64_t a, std::int64_t b, std::int64_t c) {
    return (static_cast<std::uint64_t>(a) * 73856093ull) ^
           (static_cast<std::uint64_t>(b) * 19349663ull) ^
           (static_cast<std::uint64_t>(c) * 83492791ull);
  }

  double inv_cell_;
  int dimension_;
  std::vector<NewParticle> particles_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

// A uniformly random centre that keeps a particle of radius r inside the region, or false when
// the region is too small for it.
bool RandomCentre(const RegionSpec& region, int dimension, double r, SceneRandom& random, Vec3& x) {
  x = {0, 0, 0};
  if (region.kind == RegionKind::kBox) {
    for (int d = 0; d < dimension; ++d) {
      const double lo = region.min_m[d] + r;
      const double hi = region.max_m[d] - r;
      if (hi < lo) return false;
      x[d] = random.Uniform(lo, hi);
    }
    return true;
  }
  const double reach = region.radius_m - r;
  if (reach < 0 || region.z_max_m - r < region.z_min_m + r) return false;
  for (;;) {  // rejection from the bounding square: uniform over the disk
    const double u = random.Uniform(-reach, reach);
    const double v = random.Uniform(-reach, reach);
    if (u * u + v * v <= reach * reach) {
      x = {region.center_m[0] + u, region.center_m[1] + v,
           random.Uniform(region.z_min_m + r, region.z_max_m - r)};
      return true;
    }
  }
}

bool RegionContains(const RegionSpec& region, int dimension, const Vec3& x, double margin) {
  if (region.kind == RegionKind::kBox) {
    for (int d = 0; d < dimension; ++d) {
      if (x[d] < region.min_m[d] - margin || x[d] > region.max_m[d] + margin) return false;
    }
    return true;
  }
  const double dx = x[0] - region.center_m[0];
  const double dy = x[1] - region.center_m[1];
  const double reach = region.radius_m + margin;
  return dx * dx + dy * dy <= reach * reach && x[2] >= region.z_min_m - margin &&
         x[2] <= region.z_max_m + margin;
}

}  // namespace

std::vector<NewParticle> PlaceInRegion(const Scene& scene, const std::vector<NewParticle>& pending,
                                       const std::vector<NewParticle>& existing,
                                       SceneRandom& random) {
  const auto& region = scene.insertion.region;
  double r_max = 0;
  for (const auto& p : pending) r_max = std::max(r_max, p.radius_m);
  for (const auto& p : existing) r_max = std::max(r_max, p.radius_m);
  std::vector<NewParticle> placed;
  if (pending.empty()) return placed;
  PlacementGrid grid(2 * r_max, scene.dimension);
  for (const auto& p : existing) {
    if (RegionContains(region, scene.dimension, p.position_m, 2 * r_max)) grid.Add(p);
  }
  std::int64_t attempts = 0;
  const std::int64_t budget = scene.insertion.max_attempts;
  // A pour batch stops when the region is full: that many misses in a row for one particle
  // means its free volume is a tiny fraction of the region (random sequential addition).
  const bool pour = scene.insertion.kind == InsertionKind::kPour;
  const std::int64_t miss_limit = pour ? kPourMissesPerParticle : budget;
  for (const auto& p : pending) {
    bool done = false;
    std::int64_t misses = 0;
    while (!done && attempts < budget && misses < miss_limit) {
      ++attempts;
      ++misses;
      Vec3 x;
      if (!RandomCentre(region, scene.dimension, p.radius_m, random, x)) {
        throw ConfigError(scene.source.string() +
                          ": insertion.region is smaller than a particle; make it at least one "
                          "diameter wide in every direction");
      }
      if (grid.Overlaps(x, p.radius_m)) continue;
      NewParticle q = p;
      q.position_m = x;
      grid.Add(q);
      placed.push_back(q);
      done = true;
    }
    if (!done) break;
  }
  return placed;
}

namespace {

// A particle of a start-positions file and the line it came from, for messages.
struct FileParticle {
  NewParticle particle;
  int line = 0;
};

std::vector<std::string> SplitFields(const std::string& line, bool commas) {
  std::vector<std::string> fields;
  if (commas) {
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) {
      const auto b = field.find_first_not_of(" \t\r");
      const auto e = field.find_last_not_of(" \t\r");
      fields.push_back(b == std::string::npos ? "" : field.substr(b, e - b + 1));
    }
  } else {
    std::stringstream stream(line);
    std::string field;
    while (stream >> field) fields.push_back(field);
  }
  return fields;
}

std::string Where(const std::filesystem::path& path, int line) {
  return path.string() + ":" + std::to_string(line);
}

double ParseNumber(const std::string& text, const std::filesystem::path& path, int line) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) {
    throw InputError(Where(path, line) + ": '" + text +
                     "' is not a finite number; fix the particle file");
  }
  return value;
}

// A whole number in [min, max]: species, type, id and atom counts. Checked as a double first,
// since converting a double outside the integer's range is undefined behaviour.
std::int64_t ParseWhole(const std::string& text, const std::filesystem::path& path, int line,
                        double min, double max) {
  const double value = ParseNumber(text, path, line);
  if (value != std::floor(value) || value < min || value > max) {
    throw InputError(
        fmt::format("{}: '{}' is not a whole number in [{}, {}]; fix the particle "
                    "file",
                    Where(path, line), text, min, max));
  }
  return static_cast<std::int64_t>(value);
}

// A 2D scene moves its particles in the x-y plane: a z the file gives must be 0, or the file was
// written for a 3D scene and its particles would silently be flattened onto one another.
void RefuseZIn2d(double z, const std::filesystem::path& path, int line) {
  if (z != 0) {
    throw InputError(fmt::format(
        "{}: z = {} m in a 2D scene; 2D particles lie in the x-y plane: set z to 0 or use "
        "dimension 3",
        Where(path, line), z));
  }
}

constexpr double kMaxSpecies = 1e6;

// The scene's count check (ParticleCountProblem) applied to a start-positions file.
void RefuseCount(const std::filesystem::path& path, double count, int dimension) {
  if (const auto problem = ParticleCountProblem(count, dimension)) {
    throw InputError(path.string() + ": " + *problem + "; use a file with fewer particles");
  }
}

std::vector<FileParticle> ReadCsv(std::ifstream& in, const std::filesystem::path& path,
                                  int dimension) {
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(in, line)) {
    ++line_no;
    // Spreadsheet programs often save "CSV UTF-8" with a byte order mark before the header.
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (line.empty() || line[0] == '#') continue;
    header = SplitFields(line, true);
  }
  if (header.empty()) {
    throw InputError(path.string() + ": is empty; expected a header line x_m,y_m" +
                     (dimension == 3 ? ",z_m" : "") +
                     ",diameter_m[,species] and one row per particle");
  }
  auto column = [&](const std::string& name, bool required) -> int {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) {
      if (required) {
        throw InputError(path.string() + ": the header has no '" + name +
                         "' column; expected x_m,y_m" + (dimension == 3 ? ",z_m" : "") +
                         ",diameter_m[,species]");
      }
      return -1;
    }
    return static_cast<int>(it - header.begin());
  };
  const int cx = column("x_m", true);
  const int cy = column("y_m", true);
  const int cz = column("z_m", dimension == 3);
  const int cd = column("diameter_m", true);
  const int cs = column("species", false);
  std::vector<FileParticle> out;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) {
      continue;
    }
    const auto fields = SplitFields(line, true);
    if (fields.size() != header.size()) {
      throw InputError(Where(path, line_no) + ": " + std::to_string(fields.size()) +
                       " fields where the header has " + std::to_string(header.size()));
    }
    NewParticle p;
    p.position_m[0] = ParseNumber(fields[cx], path, line_no);
    p.position_m[1] = ParseNumber(fields[cy], path, line_no);
    if (cz >= 0) {
      const double z = ParseNumber(fields[cz], path, line_no);
      if (dimension == 3) {
        p.position_m[2] = z;
      } else {
        RefuseZIn2d(z, path, line_no);
      }
    }
    p.radius_m = 0.5 * ParseNumber(fields[cd], path, line_no);
    if (cs >= 0) {
      p.species = static_cast<std::int32_t>(ParseWhole(fields[cs], path, line_no, 0, kMaxSpecies));
    }
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(Where(path, line_no) + ": diameter must be > 0 and species >= 0");
    }
    out.push_back({p, line_no});
    // Checked while reading so a runaway file is refused before it fills memory.
    if (out.size() > static_cast<std::size_t>(kMaxSceneParticles)) {
      RefuseCount(path, static_cast<double>(out.size()), dimension);
    }
  }
  return out;
}

// A LAMMPS section header (Velocities, Pair Coeffs, ...) rather than a row: ends the Atoms
// section. A row has at least 7 fields and starts with a number ("inf" and "nan" read as numbers,
// so a row holding them is refused as not finite, and a garbled row as not a number).
bool IsSectionHeader(const std::vector<std::string>& fields) {
  if (fields.size() >= 7 || !std::isalpha(static_cast<unsigned char>(fields[0][0]))) return false;
  try {
    std::size_t used = 0;
    std::stod(fields[0], &used);
    return used != fields[0].size();
  } catch (const std::exception&) {
    return true;
  }
}

std::vector<FileParticle> ReadLammpsData(std::ifstream& in, const std::filesystem::path& path,
                                         int dimension) {
  std::string line;
  int line_no = 0;
  int header_line = 0;
  std::int64_t atoms = -1;
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.size() == 2 && fields[1] == "atoms") {
      atoms = ParseWhole(fields[0], path, line_no, 0, 1e15);
      header_line = line_no;
    }
    if (!fields.empty() && fields[0] == "Atoms") break;
  }
  if (atoms < 0) {
    throw InputError(path.string() + ": no 'N atoms' header line; expected a LAMMPS data file");
  }
  RefuseCount(path, static_cast<double>(atoms), dimension);
  std::vector<std::pair<std::int64_t, FileParticle>> read;
  // The section runs to the next section header or the end of the file, not just to the
  // announced count: rows past it would otherwise be dropped without a word.
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.empty()) continue;
    if (IsSectionHeader(fields)) break;
    if (static_cast<std::int64_t>(read.size()) == atoms) {
      throw InputError(fmt::format(
          "{}: the Atoms section holds more than the {} atoms the header announces on line {}; "
          "fix the 'N atoms' line or remove the extra rows",
          Where(path, line_no), atoms, header_line));
    }
    if (fields.size() < 7) {
      throw InputError(Where(path, line_no) +
                       ": expected 'id type diameter density x y z' (atom_style sphere)");
    }
    NewParticle p;
    const auto id = ParseWhole(fields[0], path, line_no, -1e15, 1e15);
    p.species = static_cast<std::int32_t>(ParseWhole(fields[1], path, line_no, 1, kMaxSpecies)) - 1;
    p.radius_m = 0.5 * ParseNumber(fields[2], path, line_no);
    for (int d = 0; d < dimension; ++d) {
      p.position_m[d] = ParseNumber(fields[4 + d], path, line_no);
    }
    if (dimension == 2) RefuseZIn2d(ParseNumber(fields[6], path, line_no), path, line_no);
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(Where(path, line_no) + ": diameter must be > 0 and type >= 1");
    }
    read.push_back({id, {p, line_no}});
  }
  if (static_cast<std::int64_t>(read.size()) != atoms) {
    throw InputError(fmt::format(
        "{}: the Atoms section holds {} of the {} atoms the header announces; fix the 'N atoms' "
        "line or add the missing rows",
        Where(path, header_line), read.size(), atoms));
  }
  std::stable_sort(read.begin(), read.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k = 1; k < read.size(); ++k) {
    if (read[k].first == read[k - 1].first) {
      throw InputError(fmt::format(
          "{}: atom id {} appears again (first on line {}); LAMMPS atom ids must be unique",
          Where(path, read[k].second.line), read[k].first, read[k - 1].second.line));
    }
  }
  std::vector<FileParticle> out;
  out.reserve(read.size());
  for (const auto& entry : read) out.push_back(entry.second);
  return out;
}

std::string Position(const Vec3& x, int dimension) {
  return dimension == 3 ? fmt::format("({:.9g}, {:.9g}, {:.9g})", x[0], x[1], x[2])
                        : fmt::format("({:.9g}, {:.9g})", x[0], x[1]);
}

// A cell index of a grid of spacing `cell_m`, clamped so that any finite coordinate (a file may
// hold 1e300 beside 1e-6 radii) converts without overflow.
std::int64_t CellIndex(double x, double cell_m) {
  constexpr double kLimit = 0x1p62;
  const double c = std::floor(x / cell_m);
  return static_cast<std::int64_t>(std::clamp(c, -kLimit, kLimit));
}

// Two particles closer than half the sum of their radii are a duplicated row or a pack that was
// never settled: the contact law would fling them apart at the first step. A grid of cells one
// largest radius wide holds every such pair in neighbouring cells (the distance is below
// 0.5 (r_i + r_j) <= r_max); sorted by cell, each particle looks up its 27 (9 in 2D) neighbour
// cells by binary search, so a file of N particles costs O(N log N), not O(N^2).
void RefuseHeavyOverlaps(const std::vector<FileParticle>& particles,
                         const std::filesystem::path& path, int dimension) {
  double r_max = 0;
  for (const auto& f : particles) r_max = std::max(r_max, f.particle.radius_m);
  using Cell = std::array<std::int64_t, 3>;
  std::vector<Cell> cell_of(particles.size());
  std::vector<std::pair<Cell, std::size_t>> sorted(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& x = particles[i].particle.position_m;
    cell_of[i] = {CellIndex(x[0], r_max), CellIndex(x[1], r_max),
                  dimension == 3 ? CellIndex(x[2], r_max) : 0};
    sorted[i] = {cell_of[i], i};
  }
  std::sort(sorted.begin(), sorted.end());
  const std::int64_t dz = dimension == 3 ? 1 : 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const NewParticle& p = particles[i].particle;
    // The earliest particle of the file that p overlaps, so the message is the same whatever
    // the cell order.
    std::size_t partner = i;
    double partner_distance = 0;
    for (std::int64_t a = -1; a <= 1; ++a) {
      for (std::int64_t b = -1; b <= 1; ++b) {
        for (std::int64_t c = -dz; c <= dz; ++c) {
          const Cell key{cell_of[i][0] + a, cell_of[i][1] + b, cell_of[i][2] + c};
          auto it =
              std::lower_bound(sorted.begin(), sorted.end(), key,
                               [](const auto& entry, const Cell& k) { return entry.first < k; });
          for (; it != sorted.end() && it->first == key; ++it) {
            const std::size_t j = it->second;
            if (j >= partner) continue;
            const NewParticle& q = particles[j].particle;
            double dist2 = 0;
            for (int d = 0; d < dimension; ++d) {
              dist2 += (p.position_m[d] - q.position_m[d]) * (p.position_m[d] - q.position_m[d]);
            }
            const double limit = 0.5 * (p.radius_m + q.radius_m);
            if (dist2 < limit * limit) {
              partner = j;
              partner_distance = std::sqrt(dist2);
            }
          }
        }
      }
    }
    if (partner != i) {
      const NewParticle& q = particles[partner].particle;
      throw InputError(fmt::format(
          "{}: particle at {} lies {:.9g} m from the particle on line {}, closer than half the "
          "sum of their radii ({:.9g} m): a duplicated row or an unsettled pack; remove the "
          "duplicate or space them out",
          Where(path, particles[i].line), Position(p.position_m, dimension), partner_distance,
          particles[partner].line, 0.5 * (p.radius_m + q.radius_m)));
    }
  }
}

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
  auto particles = ext == ".csv" || ext == ".CSV" ? ReadCsv(in, path, dimension)
                                                  : ReadLammpsData(in, path, dimension);
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
