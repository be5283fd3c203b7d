#include "scene/insertion.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "bouncecal/error.h"
#include "bouncecal/random_stream.h"
#include "scene/overlap_checks.h"

namespace bouncecal::dem::scene {

std::uint64_t SceneRandom::Next() { return RandomStream::SplitMix64(state_); }

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
  PlacedParticles occupied(region, scene.dimension, r_max, existing.size() + pending.size());
  for (const auto& p : existing) {
    if (RegionContains(region, scene.dimension, p.position_m, 2 * r_max)) occupied.Add(p);
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
      if (occupied.Overlaps(x, p.radius_m)) continue;
      NewParticle q = p;
      q.position_m = x;
      occupied.Add(q);
      placed.push_back(q);
      done = true;
    }
    if (!done) break;
  }
  return placed;
}

}  // namespace bouncecal::dem::scene
