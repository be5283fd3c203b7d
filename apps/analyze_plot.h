#ifndef BOUNCECAL_APPS_ANALYZE_PLOT_H_
#define BOUNCECAL_APPS_ANALYZE_PLOT_H_

#include <filesystem>
#include <string>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/calibrate/restitution.h"

namespace bouncecal::apps {

// What bouncecal analyze found in one recording, as far as the plot needs it.
struct AnalyzedRecording {
  std::filesystem::path path;
  int channel = 0;
  std::vector<double> impact_onsets_s;   // impacts that belong to a bounce sequence
  std::vector<double> rejected_times_s;  // merged precursors/echoes and impacts left out
  std::vector<calibrate::RestitutionAnalysis> sequences;
};

struct AnalyzePlotOptions {
  // The waveform is high-passed at this edge for display (first order; the detector's own
  // band-pass is sharper) so DC and hum do not hide the impacts.
  double high_pass_hz = 300.0;
  // Pixel columns of the waveform; the signal is decimated to min/max per column.
  int columns = 1000;
  // Waveform panels drawn; more recordings are summarised in the energy-loss panel only.
  int max_waveform_panels = 4;
};

// One waveform panel per recording (filtered signal as a min/max envelope, impacts and
// rejected events marked) and one panel of eta_k vs k with 1-sigma bars for every sequence.
// Re-reads each file in blocks, so memory does not grow with the recording's length.
void PlotAnalysis(const std::filesystem::path& target,
                  const std::vector<AnalyzedRecording>& recordings,
                  const AnalyzePlotOptions& options = {});

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_ANALYZE_PLOT_H_
