#include "engine/energy_budget.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/dem/packing_measures.h"
#include "engine/walls.h"
#include "scene/pair_list.h"

namespace bouncecal::dem::scene {

namespace {

// Contacts per particle a van der Waals allowance is made for: a particle touches at most 12
// equal spheres (6 disks in a plane); each pair is counted once.
template <int Dim>
constexpr double kPairsPerParticle = Dim == 3 ? 6.0 : 3.0;

bool FloorBoundsTheFall(const Scene& scene) {
  const auto& c = scene.container;
  if (c.kind != ContainerKind::kPlane) return true;
  for (int d = 0; d < scene.dimension - 1; ++d) {
    if (c.normal[d] != 0) return false;
  }
  return c.normal[scene.dimension - 1] > 0;
}

// Kinetic (translation and spin) plus potential energy above the floor of particles [from, n).
template <int Dim>
double BroughtInJ(const Scene& scene, const EngineBase<Dim>& engine, std::int32_t from) {
  const auto& s = engine.state();
  const double floor = ContainerFloorM(scene);
  double joules = 0;
  for (std::int32_t i = from; i < s.size(); ++i) {
    joules += 0.5 * s.mass_kg[i] * s.velocity_mps[i].squaredNorm();
    joules += 0.5 / s.inverse_inertia[i] * SpinSquaredNorm(s.angular_velocity_radps[i]);
    joules += s.mass_kg[i] * std::max(scene.gravity_mps2, 0.0) *
              std::max(s.position_m[i][Dim - 1] - floor, 0.0);
  }
  return joules;
}

// The elastic energy the start's overlaps (particle-particle and particle-wall) can return.
template <int Dim>
double StartOverlapEnergyJ(const Scene& scene, const EngineBase<Dim>& engine) {
  const auto& s = engine.state();
  if (s.size() == 0) return 0;
  const auto law = MakeContactLaw(scene.material.law);
  auto returnable = [&](double overlap_m, double m_eff, double r_eff) {
    const NormalContact contact{overlap_m, 0, m_eff, r_eff};
    const NormalHistory fresh{};
    return std::visit([&](const auto& typed) { return typed.ReturnableEnergyJ(contact, fresh); },
                      law);
  };
  double joules = 0;
  const PairList pairs = GridPairs<Dim>(s.position_m, s.radius_m, 0.0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const auto i = static_cast<std::size_t>(pairs.first[p]);
    const auto j = static_cast<std::size_t>(pairs.second[p]);
    const double overlap =
        s.radius_m[i] + s.radius_m[j] - (s.position_m[i] - s.position_m[j]).norm();
    if (!(overlap > 0)) continue;
    joules += returnable(overlap, s.mass_kg[i] * s.mass_kg[j] / (s.mass_kg[i] + s.mass_kg[j]),
                         s.radius_m[i] * s.radius_m[j] / (s.radius_m[i] + s.radius_m[j]));
  }
  for (const auto& wall : ContainerWalls<Dim>(scene.container)) {
    for (std::size_t i = 0; i < static_cast<std::size_t>(s.size()); ++i) {
      Vec<Dim> normal;
      const double overlap = wall.Overlap(s.position_m[i], s.radius_m[i], normal);
      if (overlap > 0) joules += returnable(overlap, s.mass_kg[i], s.radius_m[i]);
    }
  }
  return joules;
}

}  // namespace

template <int Dim>
EnergyBudget::EnergyBudget(const Scene& scene, const EngineBase<Dim>& engine,
                           std::int64_t total_particles)
    : scene_(scene), bounded_(FloorBoundsTheFall(scene)) {
  joules_ = BroughtInJ(scene, engine, 0) + StartOverlapEnergyJ(scene, engine);
  if (scene.physics.van_der_waals) {
    // Each touching pair releases at most A R_eff / (6 h_min) (the Hamaker force integrated
    // from infinity to the minimum gap), R_eff at most the largest radius / 2.
    const double r_eff = 0.5 * 0.5 * scene.particles.diameter.MaxDiameterM();
    const double h = scene.material.vdw_min_gap_m;
    joules_ += kPairsPerParticle<Dim> * static_cast<double>(total_particles) *
               scene.material.hamaker_j * r_eff / (6 * h);
  }
}

template <int Dim>
void EnergyBudget::AddInserted(const EngineBase<Dim>& engine, std::int32_t first_new) {
  joules_ += BroughtInJ(scene_, engine, first_new);
}

template EnergyBudget::EnergyBudget(const Scene&, const EngineBase<2>&, std::int64_t);
template EnergyBudget::EnergyBudget(const Scene&, const EngineBase<3>&, std::int64_t);
template void EnergyBudget::AddInserted(const EngineBase<2>&, std::int32_t);
template void EnergyBudget::AddInserted(const EngineBase<3>&, std::int32_t);

}  // namespace bouncecal::dem::scene
