#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <ios>
#include <limits>

#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "scene/json_reader.h"
#include "scene/particle_file.h"

namespace bouncecal::dem {

using scene::AtMostUpToRounding;
using scene::JsonReader;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

std::filesystem::path Resolve(const std::filesystem::path& source, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || source.empty()) return p;
  return source.parent_path() / p;
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path, const std::string& what) {
  // An ifstream opens a directory without complaint; the first read then throws an
  // std::ios_base::failure ("basic_filebuf::underflow ...") that names neither file nor remedy.
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(path.string() + ": is a directory, not a " + what + "; give the file's path");
  }
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open the " + what + "; check the path");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    // parse_error, and out_of_range for a number that overflows a double (1e999).
    throw InputError(path.string() + ": not valid JSON (" + error.what() + ")");
  } catch (const std::ios_base::failure& error) {
    throw InputError(path.string() + ": cannot read the " + what + " (" + error.what() + ")");
  }
}

// Reads one part of the scene. A problem in it is recorded (JsonReader::Fail, or an InputError
// of the contact-law or material-card parser) and the caller goes on with the next part.
template <class Read>
void ReadSection(const JsonReader& root, Read&& read) {
  try {
    read();
  } catch (const scene::SectionAbandoned&) {
  } catch (const InputError& error) {
    root.Record(error.what());
  }
}

void ReadParticles(JsonReader r, Scene& scene) {
  auto& p = scene.particles;
  // Read as a double so that any count, however absurd (1e12, 2^64), is refused by the memory it
  // would need rather than by an integer range.
  const double count = r.Number("count", 1, std::numeric_limits<double>::max());
  if (count != std::floor(count)) r.Fail("count", "must be a whole number of particles");
  if (const auto problem = ParticleCountProblem(count, scene.dimension)) {
    r.Fail("count", *problem + "; use fewer particles");
  }
  p.count = static_cast<std::int64_t>(count);
  if (r.Has("diameter_m")) {
    p.diameter.kind = DiameterDistributionKind::kConstant;
    p.diameter.diameter_m = r.Number("diameter_m", 1e-9, 100);
    p.diameter.min_diameter_m = p.diameter.max_diameter_m = p.diameter.diameter_m;
  } else {
    JsonReader d = r.Object("diameter");
    const std::string kind = d.String("distribution");
    if (kind == "constant") {
      p.diameter.kind = DiameterDistributionKind::kConstant;
      p.diameter.diameter_m = d.Number("diameter_m", 1e-9, 100);
      p.diameter.min_diameter_m = p.diameter.max_diameter_m = p.diameter.diameter_m;
    } else if (kind == "uniform") {
      p.diameter.kind = DiameterDistributionKind::kUniform;
      p.diameter.min_diameter_m = d.Number("min_m", 1e-9, 100);
      p.diameter.max_diameter_m = d.Number("max_m", p.diameter.min_diameter_m, 100);
      p.diameter.diameter_m = 0.5 * (p.diameter.min_diameter_m + p.diameter.max_diameter_m);
    } else {
      d.Fail("distribution", "'" + kind + "' is not one of: constant, uniform");
    }
    d.Finish();
  }
  const auto& list = r.Raw("species");
  if (!list.is_array() || list.empty()) r.Fail("species", "must be a non-empty array of objects");
  double sum = 0;
  for (std::size_t k = 0; k < list.size(); ++k) {
    JsonReader s = r.Element(list, "species", k);
    Species species;
    species.name = s.String("name", fmt::format("species{}", k + 1));
    species.density_kg_per_m3 = s.Number("density_kg_per_m3", 1e-3, 1e6);
    // With one species the fraction is 1 and may be left out; with several it is required.
    species.volume_fraction = list.size() == 1 ? s.Number("volume_fraction", 0, 1, 1.0)
                                               : s.Number("volume_fraction", 0, 1);
    s.Finish();
    sum += species.volume_fraction;
    p.species.push_back(species);
  }
  if (std::abs(sum - 1) > 1e-6) {
    r.Fail("species", fmt::format("volume fractions sum to {:.6g}, not 1", sum));
  }
  r.Finish();
}

// True when every key the container needs was there (the insertion region is checked against it).
bool ReadContainer(JsonReader r, Scene& scene) {
  auto& c = scene.container;
  const int dim = scene.dimension;
  const std::string type = r.String("type");
  if (type == "cylinder") {
    if (dim != 3) r.Fail("type", "a cylinder needs dimension 3; use a box in 2D");
    c.kind = ContainerKind::kCylinder;
    c.center_m = r.Vector("center_m", 3, Vec3{0, 0, 0});
    c.radius_m = r.Number("radius_m", 1e-9, 1e6);
    c.height_m = r.Number("height_m", 1e-9, 1e6);
  } else if (type == "box") {
    c.kind = ContainerKind::kBox;
    c.min_m = r.Vector("min_m", dim);
    c.max_m = r.Vector("max_m", dim);
    for (int d = 0; d < dim; ++d) {
      if (!(c.max_m[d] > c.min_m[d])) r.Fail("max_m", "must exceed min_m in every component");
    }
    c.closed_top = r.Boolean("closed_top", false);
  } else if (type == "plane") {
    c.kind = ContainerKind::kPlane;
    c.point_m = r.Vector("point_m", dim, Vec3{0, 0, 0});
    Vec3 up{0, 0, 0};
    up[dim - 1] = 1;
    c.normal = r.Vector("normal", dim, up);
    double norm = 0;
    for (double x : c.normal) norm += x * x;
    if (!(norm > 0)) r.Fail("normal", "must not be the zero vector");
  } else {
    r.Fail("type", "'" + type + "' is not one of: cylinder, box, plane");
  }
  r.Finish();
  return !r.Incomplete();
}

// Particles are placed wholly inside the region (their centres a radius in from its faces), so
// the region itself must lie inside the container: a particle started across a wall is pushed
// through it or left outside, since walls act from one side only. The region may stand above an
// open container (paper 000 pours from above the rim), not above a box's lid. A region drawn
// equal to the container passes (AtMostUpToRounding).
void CheckRegionInContainer(const JsonReader& r, const RegionSpec& region, const Scene& scene) {
  static constexpr char kAxis[] = "xyz";
  const auto& c = scene.container;
  const int dim = scene.dimension;
  const int up = dim - 1;
  const bool box = region.kind == RegionKind::kBox;
  const double bottom = box ? region.min_m[up] : region.z_min_m;
  const double top = box ? region.max_m[up] : region.z_max_m;
  const char* bottom_key = box ? "min_m" : "z_min_m";
  const char* top_key = box ? "max_m" : "z_max_m";
  if (c.kind == ContainerKind::kPlane) {
    double norm = 0;
    for (int d = 0; d < dim; ++d) norm += c.normal[d] * c.normal[d];
    norm = std::sqrt(norm);
    Vec3 n{0, 0, 0};
    for (int d = 0; d < dim; ++d) n[d] = c.normal[d] / norm;
    double wall = 0;  // the plane's position along its unit normal
    for (int d = 0; d < dim; ++d) wall += c.point_m[d] * n[d];
    double lowest = 0;  // the region's lowest point along the normal
    if (box) {
      for (int d = 0; d < dim; ++d)
        lowest += n[d] * (n[d] >= 0 ? region.min_m[d] : region.max_m[d]);
    } else {
      lowest = n[0] * region.center_m[0] + n[1] * region.center_m[1] -
               region.radius_m * std::hypot(n[0], n[1]) +
               n[2] * (n[2] >= 0 ? region.z_min_m : region.z_max_m);
    }
    if (!AtMostUpToRounding(wall, lowest)) {
      r.Fail(bottom_key, fmt::format("the region reaches {:.9g} m behind the container's plane; "
                                     "particles would start behind the wall: move the region "
                                     "to the side the normal points to",
                                     wall - lowest));
    }
    return;
  }
  if (c.kind == ContainerKind::kCylinder) {
    if (box) {
      // The corner furthest from the axis.
      const double x =
          std::abs(region.min_m[0] - c.center_m[0]) > std::abs(region.max_m[0] - c.center_m[0])
              ? region.min_m[0]
              : region.max_m[0];
      const double y =
          std::abs(region.min_m[1] - c.center_m[1]) > std::abs(region.max_m[1] - c.center_m[1])
              ? region.min_m[1]
              : region.max_m[1];
      const double reach = std::hypot(x - c.center_m[0], y - c.center_m[1]);
      if (!AtMostUpToRounding(reach, c.radius_m)) {
        r.Fail(x == region.min_m[0] && y == region.min_m[1] ? "min_m" : "max_m",
               fmt::format("the region's corner (x, y) = ({:.9g}, {:.9g}) m lies {:.9g} m from "
                           "the container's axis, beyond the cylinder's radius {:.9g} m; "
                           "particles would start outside the container: keep the region "
                           "inside the cylinder",
                           x, y, reach, c.radius_m));
      }
    } else {
      const double offset =
          std::hypot(region.center_m[0] - c.center_m[0], region.center_m[1] - c.center_m[1]);
      if (!AtMostUpToRounding(offset + region.radius_m, c.radius_m)) {
        r.Fail("radius_m",
               fmt::format("the region reaches {:.9g} m from the container's axis (centre "
                           "offset {:.9g} m + radius {:.9g} m), beyond the cylinder's radius "
                           "{:.9g} m; particles would start outside the container: shrink the "
                           "region or move it onto the axis",
                           offset + region.radius_m, offset, region.radius_m, c.radius_m));
      }
    }
  } else {
    for (int d = 0; d < up; ++d) {
      const double lo = box ? region.min_m[d] : region.center_m[d] - region.radius_m;
      const double hi = box ? region.max_m[d] : region.center_m[d] + region.radius_m;
      const char* lo_key = box ? "min_m" : "radius_m";
      const char* hi_key = box ? "max_m" : "radius_m";
      if (!AtMostUpToRounding(c.min_m[d], lo)) {
        r.Fail(lo_key, fmt::format("the region reaches {0} = {1:.9g} m, beyond the container's "
                                   "side wall at {0} = {2:.9g} m; keep the region inside the box",
                                   kAxis[d], lo, c.min_m[d]));
      }
      if (!AtMostUpToRounding(hi, c.max_m[d])) {
        r.Fail(hi_key, fmt::format("the region reaches {0} = {1:.9g} m, beyond the container's "
                                   "side wall at {0} = {2:.9g} m; keep the region inside the box",
                                   kAxis[d], hi, c.max_m[d]));
      }
    }
    if (c.closed_top && !AtMostUpToRounding(top, c.max_m[up])) {
      r.Fail(top_key, fmt::format("the region reaches {0} = {1:.9g} m, above the container's "
                                  "closed top at {0} = {2:.9g} m; keep the region below the lid",
                                  kAxis[up], top, c.max_m[up]));
    }
  }
  const double floor = c.kind == ContainerKind::kCylinder ? c.center_m[2] : c.min_m[up];
  if (!AtMostUpToRounding(floor, bottom)) {
    r.Fail(bottom_key, fmt::format("the region starts at {0} = {1:.9g} m, below the container's "
                                   "floor at {0} = {2:.9g} m; particles would start under the "
                                   "floor: raise it to at least {2:.9g} m",
                                   kAxis[up], bottom, floor));
  }
}

RegionSpec ReadRegion(JsonReader r, const Scene& scene, bool container_complete) {
  const int dim = scene.dimension;
  RegionSpec region;
  const std::string type = r.String("type");
  if (type == "box") {
    region.kind = RegionKind::kBox;
    region.min_m = r.Vector("min_m", dim);
    region.max_m = r.Vector("max_m", dim);
    for (int d = 0; d < dim; ++d) {
      if (!(region.max_m[d] > region.min_m[d])) {
        r.Fail("max_m", "must exceed min_m in every component");
      }
    }
  } else if (type == "cylinder") {
    if (dim != 3) r.Fail("type", "a cylinder region needs dimension 3; use a box in 2D");
    region.kind = RegionKind::kCylinder;
    region.center_m = r.Vector("center_m", 2, Vec3{0, 0, 0});
    region.radius_m = r.Number("radius_m", 1e-9, 1e6);
    region.z_min_m = r.Number("z_min_m", -1e6, 1e6);
    region.z_max_m = r.Number("z_max_m", region.z_min_m, 1e6);
  } else {
    r.Fail("type", "'" + type + "' is not one of: box, cylinder");
  }
  r.Finish();
  // Against a container or region with a key missing, the check would judge stand-in values.
  if (container_complete && !r.Incomplete()) CheckRegionInContainer(r, region, scene);
  return region;
}

void ReadInsertion(JsonReader r, Scene& scene, bool container_complete) {
  auto& in = scene.insertion;
  const std::string type = r.String("type");
  if (type == "random" || type == "pour") {
    in.kind = type == "random" ? InsertionKind::kRandom : InsertionKind::kPour;
    in.region = ReadRegion(r.Object("region"), scene, container_complete);
    in.max_attempts = r.Integer("max_attempts", 1, std::int64_t{1} << 40, in.max_attempts);
    if (in.kind == InsertionKind::kPour) {
      in.batch_interval_s = r.Number("batch_interval_s", 1e-9, 1e6);
    }
  } else if (type == "file") {
    in.kind = InsertionKind::kFile;
    in.file = Resolve(scene.source, r.String("path"));
  } else {
    r.Fail("type", "'" + type + "' is not one of: random, pour, file");
  }
  const auto seed = r.Integer("seed", 0, std::numeric_limits<std::int64_t>::max(), 1);
  in.seed = static_cast<std::uint64_t>(seed);
  in.initial_velocity_mps = r.Vector("initial_velocity_mps", scene.dimension, Vec3{0, 0, 0});
  r.Finish();
}

void ReadMaterial(JsonReader r, Scene& scene) {
  auto& m = scene.material;
  const bool inline_law = r.Has("contact_law");
  const bool card = r.Has("material_card");
  if (inline_law == card) {
    r.Fail("contact_law", "give exactly one of 'contact_law' (inline) or 'material_card' (path)");
  }
  if (inline_law) {
    m.law = ContactLawConfigFromJson(r.Raw("contact_law"), r.file() + ": " + r.Key("contact_law"));
  } else {
    m.material_card = Resolve(scene.source, r.String("material_card"));
    const nlohmann::json card_json = ReadJsonFile(m.material_card, "material card");
    if (!card_json.is_object() || !card_json.contains("contact_law")) {
      throw InputError(m.material_card.string() +
                       ": no 'contact_law' object; is this a bouncecal material card?");
    }
    m.law = ContactLawConfigFromJson(card_json.at("contact_law"),
                                     m.material_card.string() + ": contact_law");
  }
  m.tangential_stiffness_n_per_m =
      r.Number("tangential_stiffness_n_per_m", 0, 1e15, m.tangential_stiffness_n_per_m);
  m.friction = r.Number("friction", 0, 100, m.friction);
  m.wall_friction = r.Number("wall_friction", 0, 100, m.friction);
  m.hamaker_j = r.Number("hamaker_j", 0, 1e-15, m.hamaker_j);
  m.vdw_min_gap_m = r.Number("vdw_min_gap_m", 1e-12, 1e-3, m.vdw_min_gap_m);
  m.vdw_cutoff_gap_m = r.Number("vdw_cutoff_gap_m", m.vdw_min_gap_m, 1, m.vdw_cutoff_gap_m);
  m.local_damping = r.Number("local_damping", 0, 0.999, m.local_damping);
  const std::string scope = r.String("local_damping_scope", "unbalanced-force");
  if (scope == "unbalanced-force") {
    m.local_damping_scope = LocalDampingScope::kUnbalancedForce;
  } else if (scope == "contact-forces") {
    m.local_damping_scope = LocalDampingScope::kContactForces;
  } else {
    r.Fail("local_damping_scope",
           "'" + scope + "' is not one of: unbalanced-force (gravity damped too, Itasca PFC), " +
               "contact-forces (gravity undamped)");
  }
  r.Finish();
}

void ReadPhysics(JsonReader r, Scene& scene) {
  auto& p = scene.physics;
  p.tangential = r.Boolean("tangential", p.tangential);
  p.rotation = r.Boolean("rotation", p.tangential);
  p.van_der_waals = r.Boolean("van_der_waals", false);
  p.local_damping = r.Boolean("local_damping", false);
  p.stop_at_first_contact = r.Boolean("stop_at_first_contact", false);
  if (p.rotation && !p.tangential) {
    r.Fail("rotation", "needs tangential: true (only the tangential force makes torque)");
  }
  r.Finish();
}

void ReadMeasurement(JsonReader r, Scene& scene) {
  auto& m = scene.measurement;
  if (scene.dimension == 3) {
    const Vec3 band = r.Vector("band_m", 2);
    if (!(band[1] > band[0])) r.Fail("band_m", "must be [low, high] with high > low");
    m.band_min_m = band[0];
    m.band_max_m = band[1];
  } else {
    JsonReader w = r.Object("window");
    m.window_min_m = w.Vector("min_m", 2);
    m.window_max_m = w.Vector("max_m", 2);
    if (!(m.window_max_m[0] > m.window_min_m[0] && m.window_max_m[1] > m.window_min_m[1])) {
      w.Fail("max_m", "must exceed min_m in both components");
    }
    w.Finish();
  }
  m.profile_bin_m = r.Number("profile_bin_m", 0, 1e6, 0);
  m.contact_tolerance = r.Number("contact_tolerance", 1, 2, m.contact_tolerance);
  m.history_interval_s = r.Number("history_interval_s", 0, 1e6, m.history_interval_s);
  r.Finish();
}

void ReadOutputs(JsonReader r, Scene& scene) {
  auto& o = scene.outputs;
  o.directory = Resolve(scene.source, r.String("directory", scene.name + "_out"));
  o.snapshot_interval_s = r.Number("snapshot_interval_s", 0, 1e6, 0);
  r.Finish();
}

}  // namespace

double DiameterDistribution::MaxDiameterM() const {
  return kind == DiameterDistributionKind::kConstant ? diameter_m : max_diameter_m;
}

double DiameterDistribution::MeanVolumeM3(int dimension) const {
  // Mean of pi d^3/6 (or pi d^2/4) over the distribution.
  if (kind == DiameterDistributionKind::kConstant) {
    return dimension == 3 ? kPi * std::pow(diameter_m, 3) / 6 : kPi * diameter_m * diameter_m / 4;
  }
  const double a = min_diameter_m;
  const double b = max_diameter_m;
  if (b <= a) return DiameterDistribution{kind, a, a, a}.MeanVolumeM3(dimension);
  return dimension == 3 ? kPi / 6 * (std::pow(b, 4) - std::pow(a, 4)) / (4 * (b - a))
                        : kPi / 4 * (std::pow(b, 3) - std::pow(a, 3)) / (3 * (b - a));
}

std::int64_t EstimatedBytesPerParticle(int dimension) {
  // State (~20 doubles), wall history (6 walls), ~8 listed pairs of 12 doubles each, grid.
  return dimension == 3 ? 1400 : 800;
}

std::optional<std::string> ParticleCountProblem(double count, int dimension) {
  const double bytes = count * static_cast<double>(EstimatedBytesPerParticle(dimension));
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  const double memory = pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size : kInf;
  // 0.8: the rest of the process (outputs, measurement buffers) and the system need room too.
  if (count <= static_cast<double>(kMaxSceneParticles) && bytes <= 0.8 * memory) {
    return std::nullopt;
  }
  return fmt::format(
      "{} particles would need about {:.1f} GB of memory (this machine has {:.1f} GB, the limit "
      "is {} particles)",
      count, bytes / 1e9, memory / 1e9, kMaxSceneParticles);
}

std::string_view ToString(ContainerKind kind) {
  switch (kind) {
    case ContainerKind::kPlane:
      return "plane";
    case ContainerKind::kCylinder:
      return "cylinder";
    case ContainerKind::kBox:
      return "box";
  }
  return "unknown";
}

std::string_view ToString(InsertionKind kind) {
  switch (kind) {
    case InsertionKind::kRandom:
      return "random";
    case InsertionKind::kPour:
      return "pour";
    case InsertionKind::kFile:
      return "file";
  }
  return "unknown";
}

Scene SceneFromJson(const nlohmann::json& root, const std::filesystem::path& source) {
  const std::string file = source.empty() ? std::string("scene") : source.string();
  JsonReader r(root, file, "");
  Scene scene;
  scene.source = source;
  ReadSection(r, [&] {
    const std::string format = r.String("format");
    if (format != "bouncecal-scene/1") {
      r.Fail("format", "'" + format + "' is not a known scene format; expected bouncecal-scene/1");
    }
  });
  // Not a scene of this format: its other keys would be reported against the wrong list.
  r.ThrowProblems();
  ReadSection(r, [&] {
    const bool named = r.Has("name");
    scene.name = r.String("name", source.empty() ? std::string("scene") : source.stem().string());
    // The name becomes the default output folder (NAME_out) and plot titles: one path component.
    if (named && (scene.name.empty() || scene.name == "." || scene.name == ".." ||
                  scene.name.find_first_of("/\\\"'`") != std::string::npos ||
                  std::any_of(scene.name.begin(), scene.name.end(),
                              [](unsigned char c) { return c < 0x20 || c == 0x7f; }))) {
      r.Fail("name",
             "must be a non-empty file-name-like word (no slashes, quotes or control "
             "characters): it names the output folder");
    }
  });
  ReadSection(r, [&] { r.String("description", ""); });
  ReadSection(r, [&] { scene.dimension = static_cast<int>(r.Integer("dimension", 2, 3, 3)); });
  // Every other part depends on the dimension (vector sizes, which keys exist).
  r.ThrowProblems();
  // Each part is read even when an earlier one has a problem, so that one error names every
  // missing and unknown key (JsonReader).
  ReadSection(r, [&] { ReadParticles(r.Object("particles"), scene); });
  bool container_complete = false;
  ReadSection(r, [&] { container_complete = ReadContainer(r.Object("container"), scene); });
  ReadSection(r, [&] { ReadInsertion(r.Object("insertion"), scene, container_complete); });
  ReadSection(r, [&] { ReadMaterial(r.Object("material"), scene); });
  ReadSection(r, [&] { ReadPhysics(r.OptionalObject("physics"), scene); });
  ReadSection(r, [&] { scene.time_step_s = r.Number("time_step_s", 1e-12, 1); });
  ReadSection(r, [&] { scene.time_step_reason = r.String("time_step_reason", ""); });
  ReadSection(r, [&] { scene.duration_s = r.Number("duration_s", 0, 1e6); });
  ReadSection(r,
              [&] { scene.gravity_mps2 = r.Number("gravity_mps2", 0, 1e4, scene.gravity_mps2); });
  ReadSection(r, [&] { ReadMeasurement(r.Object("measurement"), scene); });
  ReadSection(r, [&] { ReadOutputs(r.OptionalObject("outputs"), scene); });
  r.Finish();
  r.ThrowProblems();
  // The start-positions file is part of the scene: checked now (against the container, the
  // species and particles.count), so a bad one is refused before any output is written.
  if (scene.insertion.kind == InsertionKind::kFile) {
    const auto particles = scene::ReadParticleFile(scene);
    scene.insertion.start_particles.reserve(particles.size());
    for (const auto& p : particles) {
      scene.insertion.start_particles.push_back({p.position_m, p.radius_m, p.species});
    }
  }
  return scene;
}

Scene LoadScene(const std::filesystem::path& path) {
  return SceneFromJson(ReadJsonFile(path, "scene file"), path);
}

}  // namespace bouncecal::dem
