#ifndef BOUNCECAL_DEM_ENGINE_REST_CHECKS_H_
#define BOUNCECAL_DEM_ENGINE_REST_CHECKS_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/packing.h"

namespace bouncecal::dem::scene {

// A packing is read at rest: kinetic energy at the end above this fraction of its peak means it
// was not (a pour at rest keeps ~1e-6 of it, paper 000 1.3e-5 J of ~10 J).
inline constexpr double kAtRestFraction = 1e-2;

// A warning when the run ended while its particles still moved: cut short, or boiling (a pack
// gaining energy from a coarse step as fast as its damping removes it stays under the energy
// budget but never settles).
std::optional<std::string> NotAtRest(const std::vector<HistoryPoint>& history);

// A run that is not at rest (NotAtRest) is boiling rather than cut short when its kinetic energy
// has stopped falling: over the second half of the time since its peak, with no particle poured
// meanwhile, it fell by less than half. A pack settling under its damping loses orders of
// magnitude over that time, and one still falling gains energy towards its end (its peak is
// the last sample); one that keeps half of it is being heated by its integrator as fast as the
// damping cools it (a time step too coarse for the contacts it has, though under the limit of
// one contact).
bool Boiling(const std::vector<HistoryPoint>& history);

// Why a Boiling run's measures are not a packing, and what to do, in one sentence: where its
// kinetic energy stopped falling (the last sample, and its share of the peak) and the step.
std::string BoilingMessage(const std::vector<HistoryPoint>& history, double time_step_s);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_REST_CHECKS_H_
