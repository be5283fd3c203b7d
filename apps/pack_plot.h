#ifndef BOUNCECAL_APPS_PACK_PLOT_H_
#define BOUNCECAL_APPS_PACK_PLOT_H_

#include <filesystem>

#include "bouncecal/dem/scene.h"

namespace bouncecal::apps {

// `pack --plot`: profile.png and history.png, drawn by gnuplot from the tables WritePackTables
// wrote, with the script beside them as plots.gp. Throws OutputError when gnuplot fails.
void PlotPacking(const std::filesystem::path& dir, const dem::Scene& scene);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PACK_PLOT_H_
