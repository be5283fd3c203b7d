#include "scene/insertion.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
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

double ParseNumber(const std::string& text, const std::filesystem::path& path, int line) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) {
    throw InputError(path.string() + ":" + std::to_string(line) + ": '" + text +
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
        fmt::format("{}:{}: '{}' is not a whole number in [{}, {}]; fix the particle "
                    "file",
                    path.string(), line, text, min, max));
  }
  return static_cast<std::int64_t>(value);
}

constexpr double kMaxSpecies = 1e6;

// The scene's count check (ParticleCountProblem) applied to a start-positions file.
void RefuseCount(const std::filesystem::path& path, double count, int dimension) {
  if (const auto problem = ParticleCountProblem(count, dimension)) {
    throw InputError(path.string() + ": " + *problem + "; use a file with fewer particles");
  }
}

std::vector<NewParticle> ReadCsv(std::ifstream& in, const std::filesystem::path& path,
                                 int dimension) {
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    header = SplitFields(line, true);
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
  std::vector<NewParticle> out;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) {
      continue;
    }
    const auto fields = SplitFields(line, true);
    if (fields.size() != header.size()) {
      throw InputError(path.string() + ":" + std::to_string(line_no) + ": " +
                       std::to_string(fields.size()) + " fields where the header has " +
                       std::to_string(header.size()));
    }
    NewParticle p;
    p.position_m[0] = ParseNumber(fields[cx], path, line_no);
    p.position_m[1] = ParseNumber(fields[cy], path, line_no);
    if (cz >= 0 && dimension == 3) p.position_m[2] = ParseNumber(fields[cz], path, line_no);
    p.radius_m = 0.5 * ParseNumber(fields[cd], path, line_no);
    if (cs >= 0) {
      p.species = static_cast<std::int32_t>(ParseWhole(fields[cs], path, line_no, 0, kMaxSpecies));
    }
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(path.string() + ":" + std::to_string(line_no) +
                       ": diameter must be > 0 and species >= 0");
    }
    out.push_back(p);
    // Checked while reading so a runaway file is refused before it fills memory.
    if (out.size() > static_cast<std::size_t>(kMaxSceneParticles)) {
      RefuseCount(path, static_cast<double>(out.size()), dimension);
    }
  }
  return out;
}

std::vector<NewParticle> ReadLammpsData(std::ifstream& in, const std::filesystem::path& path,
                                        int dimension) {
  std::string line;
  int line_no = 0;
  std::int64_t atoms = -1;
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.size() == 2 && fields[1] == "atoms") {
      atoms = ParseWhole(fields[0], path, line_no, 0, 1e15);
    }
    if (!fields.empty() && fields[0] == "Atoms") break;
  }
  if (atoms < 0) {
    throw InputError(path.string() + ": no 'N atoms' header line; expected a LAMMPS data file");
  }
  RefuseCount(path, static_cast<double>(atoms), dimension);
  std::vector<std::pair<std::int64_t, NewParticle>> read;
  while (static_cast<std::int64_t>(read.size()) < atoms && std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.empty()) continue;
    if (fields.size() < 7) {
      throw InputError(path.string() + ":" + std::to_string(line_no) +
                       ": expected 'id type diameter density x y z' (atom_style sphere)");
    }
    NewParticle p;
    const auto id = ParseWhole(fields[0], path, line_no, -1e15, 1e15);
    p.species = static_cast<std::int32_t>(ParseWhole(fields[1], path, line_no, 1, kMaxSpecies)) - 1;
    p.radius_m = 0.5 * ParseNumber(fields[2], path, line_no);
    for (int d = 0; d < dimension; ++d) {
      p.position_m[d] = ParseNumber(fields[4 + d], path, line_no);
    }
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(path.string() + ":" + std::to_string(line_no) +
                       ": diameter must be > 0 and type >= 1");
    }
    read.emplace_back(id, p);
  }
  if (static_cast<std::int64_t>(read.size()) != atoms) {
    throw InputError(path.string() + ": the Atoms section holds " + std::to_string(read.size()) +
                     " of the " + std::to_string(atoms) + " atoms the header announces");
  }
  std::stable_sort(read.begin(), read.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<NewParticle> out;
  for (const auto& [id, p] : read) out.push_back(p);
  return out;
}

}  // namespace

std::vector<NewParticle> ReadParticleFile(const std::filesystem::path& path, int dimension) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(path.string() + ": cannot open the particle file; check insertion.file");
  }
  const auto ext = path.extension().string();
  auto particles = ext == ".csv" || ext == ".CSV" ? ReadCsv(in, path, dimension)
                                                  : ReadLammpsData(in, path, dimension);
  RefuseCount(path, static_cast<double>(particles.size()), dimension);
  return particles;
}

}  // namespace bouncecal::dem::scene
