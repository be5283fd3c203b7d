#include "simulate_plot.h"

#include <fmt/core.h>

#include <algorithm>

#include "bouncecal/error.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {

void PlotDrop(const std::filesystem::path& target, const dem::DropResult& result,
              const std::string& description, std::size_t max_points) {
  if (result.trajectory.empty()) {
    throw ConfigError("the drop has no trajectory to plot; use a positive --trajectory-interval");
  }
  PlotPanel heights;
  heights.title = "Simulated drop: " + description;
  heights.x_label = "time t (s)";
  heights.y_label = "height of the ball's lowest point z (m)";
  heights.legend_position = "top right";
  PlotSeries arc;
  arc.title = "z(t)";
  const std::size_t stride = std::max<std::size_t>(1, result.trajectory.size() / max_points + 1);
  for (std::size_t i = 0; i < result.trajectory.size(); i += stride) {
    arc.x.push_back(result.trajectory[i].time_s);
    arc.y.push_back(result.trajectory[i].height_m);
  }
  heights.series.push_back(std::move(arc));
  PlotPanel energy;
  energy.title = "Energy loss per impact";
  energy.x_label = "impact number k";
  energy.integer_x = true;
  energy.y_label = "energy loss eta_k = 1 - e_k^2 (1)";
  PlotSeries impacts;
  impacts.title = "impact (start of contact)";
  impacts.style = SeriesStyle::kPoints;
  impacts.point_type = 9;
  PlotSeries losses;
  losses.title = "simulated eta_k";
  losses.style = SeriesStyle::kLinesPoints;
  for (std::size_t k = 0; k < result.impacts.size(); ++k) {
    impacts.x.push_back(result.impacts[k].time_s);
    impacts.y.push_back(0.0);
    if (result.impacts[k].released) {
      losses.x.push_back(static_cast<double>(k + 1));
      losses.y.push_back(result.impacts[k].energy_loss);
    }
  }
  std::vector<PlotPanel> panels;
  if (!impacts.x.empty()) heights.series.push_back(std::move(impacts));
  panels.push_back(std::move(heights));
  if (!losses.x.empty()) {
    energy.x_range = std::make_pair(0.0, losses.x.back() + 1);
    energy.series.push_back(std::move(losses));
    panels.push_back(std::move(energy));
  }
  RenderPlot(target, panels);
}

}  // namespace bouncecal::apps
