#include "engine/rest_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>

namespace bouncecal::dem::scene {

namespace {
// At least this many samples after the peak, so the halves compared are not one sample each.
constexpr std::size_t kBoilingSamples = 4;
constexpr double kBoilingKeptFraction = 0.5;

}  // namespace

std::optional<std::string> NotAtRest(const std::vector<HistoryPoint>& history) {
  if (history.size() < 2) return std::nullopt;
  const auto peak = std::max_element(history.begin(), history.end(),
                                     [](const HistoryPoint& a, const HistoryPoint& b) {
                                       return a.kinetic_energy_j < b.kinetic_energy_j;
                                     });
  const double last = history.back().kinetic_energy_j;
  if (!(peak->kinetic_energy_j > 0) || !(last > kAtRestFraction * peak->kinetic_energy_j)) {
    return std::nullopt;
  }
  return fmt::format(
      "the particles have not come to rest: the kinetic energy at the end, {:.3g} J, is {:.0f} % "
      "of its peak ({:.3g} J at t = {:.3g} s); the packing measures describe a moving state. Run "
      "longer, or, if it does not fall, use a smaller time_step_s",
      last, 100 * last / peak->kinetic_energy_j, peak->kinetic_energy_j, peak->time_s);
}

bool Boiling(const std::vector<HistoryPoint>& history) {
  if (history.size() < 2) return false;
  const auto peak = std::max_element(history.begin(), history.end(),
                                     [](const HistoryPoint& a, const HistoryPoint& b) {
                                       return a.kinetic_energy_j < b.kinetic_energy_j;
                                     });
  const auto& last = history.back();
  const auto after = static_cast<std::size_t>(history.end() - peak) - 1;
  if (after < kBoilingSamples || peak->particles != last.particles) return false;
  if (!(last.kinetic_energy_j > kAtRestFraction * peak->kinetic_energy_j)) return false;
  const auto& middle = *(peak + static_cast<std::ptrdiff_t>(after / 2));
  return last.kinetic_energy_j >= kBoilingKeptFraction * middle.kinetic_energy_j;
}

std::string BoilingMessage(const std::vector<HistoryPoint>& history, double time_step_s) {
  const auto peak = std::max_element(history.begin(), history.end(),
                                     [](const HistoryPoint& a, const HistoryPoint& b) {
                                       return a.kinetic_energy_j < b.kinetic_energy_j;
                                     });
  const double last = history.empty() ? 0.0 : history.back().kinetic_energy_j;
  const double share = peak != history.end() && peak->kinetic_energy_j > 0
                           ? 100 * last / peak->kinetic_energy_j
                           : 0.0;
  return fmt::format(
      "the particles never came to rest: their kinetic energy stopped falling at {:.3g} J ({:.0f} "
      "% of its peak), so the step of {:.3g} s heats the pack as fast as its damping cools it; "
      "the outputs describe a boiling state. Use a smaller time_step_s",
      last, share, time_step_s);
}

}  // namespace bouncecal::dem::scene
