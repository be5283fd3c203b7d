#ifndef BOUNCECAL_APPS_SIMULATE_PLOT_H_
#define BOUNCECAL_APPS_SIMULATE_PLOT_H_

#include <filesystem>
#include <string>

#include "bouncecal/dem/drop.h"

namespace bouncecal::apps {

// Height of the ball's lowest point vs time with the impacts marked, and eta_k vs k. The
// trajectory is thinned to at most max_points points (an arc needs a few hundred, a drop to rest
// at 0.1 ms sampling can have 10^5 or more).
void PlotDrop(const std::filesystem::path& target, const dem::DropResult& result,
              const std::string& description, std::size_t max_points = 5000);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_SIMULATE_PLOT_H_
