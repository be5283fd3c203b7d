#include "analyze_plot.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "display_waveform.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

PlotPanel WaveformPanel(const AnalyzedRecording& recording, const AnalyzePlotOptions& options) {
  const auto columns =
      DisplayWaveform(recording.path, recording.channel, options.high_pass_hz, options.columns);
  double peak = 1e-6;
  for (std::size_t c = 0; c < columns.min.size(); ++c) {
    peak = std::max({peak, std::abs(columns.min[c]), std::abs(columns.max[c])});
  }
  PlotPanel panel;
  panel.title =
      fmt::format("{} (channel {}, high-passed at {:g} Hz for display)",
                  recording.path.filename().string(), recording.channel, options.high_pass_hz);
  panel.x_label = "time t (s)";
  panel.y_label = "amplitude (full scale = 1)";
  panel.legend_position = "outside right top";
  PlotSeries waveform;
  waveform.title = "signal (min/max per pixel)";
  waveform.style = SeriesStyle::kBand;
  waveform.x = columns.time_s;
  waveform.y = columns.min;
  waveform.y_high = columns.max;
  panel.series.push_back(std::move(waveform));
  // Markers sit in rows above and below the trace so they never cover it.
  PlotSeries impacts;
  impacts.title = fmt::format("impact ({})", recording.impact_onsets_s.size());
  impacts.style = SeriesStyle::kPoints;
  impacts.point_type = 11;
  impacts.point_size = 1.3;
  impacts.x = recording.impact_onsets_s;
  impacts.y.assign(impacts.x.size(), 1.12 * peak);
  PlotSeries rejected;
  rejected.title = fmt::format("rejected event ({})", recording.rejected_times_s.size());
  rejected.style = SeriesStyle::kPoints;
  rejected.point_type = 2;
  rejected.point_size = 1.5;
  rejected.x = recording.rejected_times_s;
  rejected.y.assign(rejected.x.size(), -1.12 * peak);
  // gnuplot needs at least one point per series; an empty marker row is left out instead.
  if (!impacts.x.empty()) panel.series.push_back(std::move(impacts));
  if (!rejected.x.empty()) panel.series.push_back(std::move(rejected));
  panel.y_range = std::make_pair(-1.25 * peak, 1.25 * peak);
  if (!columns.time_s.empty()) {
    panel.x_range = std::make_pair(0.0, columns.time_s.back());
  }
  return panel;
}

}  // namespace

void PlotAnalysis(const std::filesystem::path& target,
                  const std::vector<AnalyzedRecording>& recordings,
                  const AnalyzePlotOptions& options) {
  std::vector<PlotPanel> panels;
  const std::size_t waveforms = std::min(
      recordings.size(), static_cast<std::size_t>(std::max(options.max_waveform_panels, 0)));
  for (std::size_t r = 0; r < waveforms; ++r)
    panels.push_back(WaveformPanel(recordings[r], options));

  PlotPanel energy;
  energy.title =
      "Energy loss per impact, eta_k = 1 - e_k^2 (1-sigma bars from the onset uncertainty)";
  energy.x_label = "impact number k";
  energy.integer_x = true;
  energy.y_label = "energy loss eta_k (1)";
  energy.legend_position = "outside right top";
  double last_k = 1;
  for (const auto& recording : recordings) {
    for (std::size_t s = 0; s < recording.sequences.size(); ++s) {
      const auto& physics = recording.sequences[s];
      if (physics.energy_loss.empty()) continue;
      PlotSeries series;
      series.title = recordings.size() > 1 || recording.sequences.size() > 1
                         ? fmt::format("{} seq {}", recording.path.filename().string(), s)
                         : std::string("measured");
      series.style = SeriesStyle::kErrorBars;
      for (std::size_t j = 0; j < physics.energy_loss.size(); ++j) {
        series.x.push_back(physics.impact_index[j] + 1);
        series.y.push_back(physics.energy_loss[j]);
        series.y_error.push_back(physics.energy_loss_uncertainty[j]);
        last_k = std::max(last_k, series.x.back());
      }
      energy.series.push_back(std::move(series));
    }
  }
  if (energy.series.empty()) {
    // Keep the panel so the figure says why it is empty instead of failing.
    energy.title = "Energy loss per impact: no bounce sequence with two intervals was found";
    energy.series.push_back({"(none)", {1}, {0}, {}, SeriesStyle::kPoints, false, {}, 7, 0.0});
  }
  energy.x_range = std::make_pair(0.0, last_k + 1);
  panels.push_back(std::move(energy));
  PlotOptions plot_options;
  plot_options.height_px_per_panel = 360;
  RenderPlot(target, panels, plot_options);
}

}  // namespace bouncecal::apps
