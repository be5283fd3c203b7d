#include "bouncecal/dem/pack_projection.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace bouncecal::dem {
namespace {

struct ReferenceRow {
  double particles;
  double particle_steps_per_s;  // settled pack, per thread
};

// Settled packs per thread (particle-steps per cpu-second of a 2-thread run, set-up included),
// from the scale table of docs/packing.md (bench/pack_scale.py, 2026-11-28, the shared 2-core
// development host): the costly regime, so a pour's falling phase runs ahead of the projection.
// Past the last row the speed is held: per particle-step the engine's memory traffic stops
// growing once the state is far larger than the caches.
constexpr ReferenceRow kReference[] = {
    {2e3, 1.6e7},
    {2e4, 9.2e6},
    {1e5, 6.4e6},
    {1e6, 4.1e6},
};

// Each thread past the first adds this share of one: 2 threads ran the 2000-sphere settled pack
// 1.28x and the whole pour 1.6x as fast as 1 (docs/history/packing_speed_rounds.md, seventh
// round); larger packs split better, smaller ones worse.
constexpr double kExtraThreadShare = 0.5;

// Time constant (wall seconds) of the smoothing of the measured speed: long enough to ride over
// one neighbour rebuild or a pour batch, short enough to follow a pour settling.
constexpr double kSmoothingS = 5.0;

std::string Duration(double s) {
  if (!std::isfinite(s)) return "an unknown time";
  if (s < 60) return fmt::format("{:.0f} s", std::max(s, 1.0));
  if (s < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
  if (s < 86400 * 2) {
    return fmt::format("{:.0f} h {:02.0f} min", std::floor(s / 3600), std::fmod(s, 3600) / 60);
  }
  return fmt::format("{:.1f} days", s / 86400);
}

}  // namespace

double ReferenceParticleStepsPerS(std::int64_t particles, int threads) {
  const double n = std::max<double>(1, static_cast<double>(particles));
  double rate = kReference[0].particle_steps_per_s;
  if (n >= std::prev(std::end(kReference))->particles) {
    rate = std::prev(std::end(kReference))->particle_steps_per_s;
  } else if (n > kReference[0].particles) {
    for (std::size_t r = 1; r < std::size(kReference); ++r) {
      if (n > kReference[r].particles) continue;
      const auto& lo = kReference[r - 1];
      const auto& hi = kReference[r];
      const double f = std::log(n / lo.particles) / std::log(hi.particles / lo.particles);
      rate = std::exp(std::log(lo.particle_steps_per_s) +
                      f * std::log(hi.particle_steps_per_s / lo.particle_steps_per_s));
      break;
    }
  }
  return rate * (1 + kExtraThreadShare * std::max(0, threads - 1));
}

double ProjectWallTimeS(std::int64_t particles, std::int64_t steps, int threads) {
  return static_cast<double>(particles) * static_cast<double>(steps) /
         ReferenceParticleStepsPerS(particles, threads);
}

double ProjectWallTimeS(const Scene& scene, const PackOptions& options) {
  const double duration = options.duration_s.value_or(scene.duration_s);
  const auto steps = static_cast<std::int64_t>(std::llround(duration / scene.time_step_s));
  return ProjectWallTimeS(scene.particles.count, steps, options.threads);
}

std::string DescribeProjection(const Scene& scene, const PackOptions& options) {
  const double duration = options.duration_s.value_or(scene.duration_s);
  const auto steps = static_cast<std::int64_t>(std::llround(duration / scene.time_step_s));
  return fmt::format(
      "projected wall time: about {} for {} particles x {} steps on {} thread(s) (the reference "
      "host's settled-pack speed, {:.3g} particle-steps/s; the progress line measures this run's)",
      Duration(ProjectWallTimeS(scene, options)), scene.particles.count, steps, options.threads,
      ReferenceParticleStepsPerS(scene.particles.count, options.threads));
}

WallTimeProjection::WallTimeProjection(std::int64_t final_particles, std::int64_t total_steps,
                                       int threads, std::int64_t first_step, double first_wall_s)
    : final_particles_(final_particles),
      total_steps_(total_steps),
      prior_s_(ProjectWallTimeS(final_particles,
                                std::max<std::int64_t>(0, total_steps - first_step), threads)),
      prior_rate_(ReferenceParticleStepsPerS(final_particles, threads)),
      last_steps_(first_step),
      last_wall_s_(first_wall_s) {}

double WallTimeProjection::Update(std::int64_t steps_done, std::int64_t particles, double wall_s) {
  const double interval_s = wall_s - last_wall_s_;
  const std::int64_t interval_steps = steps_done - last_steps_;
  if (interval_s > 0 && interval_steps > 0 && particles > 0) {
    const double measured =
        static_cast<double>(particles) * static_cast<double>(interval_steps) / interval_s;
    const double weight = rate_ > 0 ? 1 - std::exp(-interval_s / kSmoothingS) : 1.0;
    rate_ += weight * (measured - rate_);
    last_wall_s_ = wall_s;
    last_steps_ = steps_done;
  }
  const double remaining_particle_steps =
      static_cast<double>(std::max<std::int64_t>(0, total_steps_ - steps_done)) *
      static_cast<double>(final_particles_);
  return remaining_particle_steps / (rate_ > 0 ? rate_ : prior_rate_);
}

}  // namespace bouncecal::dem
