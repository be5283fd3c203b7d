#ifndef BOUNCECAL_DEM_ENGINE_PARTICLE_RECORDS_H_
#define BOUNCECAL_DEM_ENGINE_PARTICLE_RECORDS_H_

// The packing engine's particle record: everything the stepping loop reads of one particle, laid
// out for the cache. ParticleState (engine.h) keeps one array per quantity, which is what
// callers, the neighbour rebuild and the first-contact stop want; the stepping loop instead
// works on one 128-byte record per particle, so a pair's far member costs two cache lines
// fetched together instead of a line in each of several arrays, and the kick-drift reads one
// record. Both copies hold the same values, so the arithmetic does not depend on which is used.

#include <cstddef>
#include <vector>

#include "engine/engine.h"
#include "scene/vec.h"

namespace bouncecal::dem::scene {

// A vector and one scalar of a particle in one aligned 32-byte row, so that a pair's member
// costs one cache line per quantity instead of two or three (a 24-byte Vec straddles a line
// boundary in 3 of 8 slots, and the scalar lives in another array). The dense pair pass reads
// the rows of four particles whole and transposes them (simd_helpers.h).
template <int Dim>
struct alignas(32) PackedVector {
  Vec<Dim> v;
  double s;
};
template <int Dim>
struct alignas(Dim == 3 ? 32 : 16) PackedSpin {
  Spin<Dim> w;
  double inverse_inertia;
};

// One particle for the stepping loop, two cache lines.
template <int Dim>
struct alignas(64) ParticleRecord {
  PackedVector<Dim> position_radius;
  PackedVector<Dim> velocity_mass;
  PackedSpin<Dim> spin_inertia;
  Vec<Dim> origin;  // the position at the last neighbour-list build
  double inverse_mass;
};

// The records of every particle of `state`, with `origin_m` the positions at the last rebuild.
template <int Dim>
void LoadParticleRecords(const ParticleState<Dim>& state, const std::vector<Vec<Dim>>& origin_m,
                         std::vector<ParticleRecord<Dim>>& records) {
  const auto n = static_cast<std::size_t>(state.size());
  records.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    records[i].position_radius = {state.position_m[i], state.radius_m[i]};
    records[i].velocity_mass = {state.velocity_mps[i], state.mass_kg[i]};
    records[i].spin_inertia = {state.angular_velocity_radps[i], state.inverse_inertia[i]};
    records[i].origin = origin_m[i];
    records[i].inverse_mass = state.inverse_mass[i];
  }
}

// Hands back what the stepping loop changes: positions, velocities and spins.
template <int Dim>
void StoreParticleRecords(const std::vector<ParticleRecord<Dim>>& records,
                          ParticleState<Dim>& state) {
  const auto n = static_cast<std::size_t>(state.size());
  for (std::size_t i = 0; i < n; ++i) {
    state.position_m[i] = records[i].position_radius.v;
    state.velocity_mps[i] = records[i].velocity_mass.v;
    state.angular_velocity_radps[i] = records[i].spin_inertia.w;
  }
}

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_PARTICLE_RECORDS_H_
