#ifndef BOUNCECAL_APPS_WAVEFORM_SVG_H_
#define BOUNCECAL_APPS_WAVEFORM_SVG_H_

#include <string>

#include "report_recordings.h"

namespace bouncecal::apps {

// Layout of the figure, in SVG user units (pixels at 100 %). The plot area is as wide as the
// waveform has columns (RecordingViewOptions::columns), so each column is one pixel.
struct WaveformSvgLayout {
  double width = 1000;
  double height = 330;
  double left = 70;  // plot area: x from left to width - right
  double right = 20;
  double wave_top = 90;  // waveform band: y from wave_top to wave_bottom
  double wave_bottom = 240;
};

// One recording as an inline <svg> element for the HTML report, written by hand (not gnuplot) so
// every marker carries its own tooltip (<title>) and nothing needs a script: the min/max
// waveform, a down triangle over every impact of a bounce sequence (coloured by sequence, with a
// faint line through the trace), a bracket over each sequence with its name, and a cross under
// every rejected event whose tooltip gives the reason. Time runs from 0 to the recording's
// duration on the x axis. The plot area carries data-t0-s and data-t1-s, the markers data-time-s,
// for readers (and the browser test) that map positions back to times.
std::string WaveformSvg(const RecordingView& view, const WaveformSvgLayout& layout = {});

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_WAVEFORM_SVG_H_
