#ifndef BOUNCECAL_APPS_REPORT_RECORDINGS_H_
#define BOUNCECAL_APPS_REPORT_RECORDINGS_H_

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/calibrate/sequence_input.h"
#include "plot/min_max_decimator.h"

namespace bouncecal::apps {

// A bounce sequence as the fit names it ("drop.wav#1") with its impact onsets.
struct ViewedSequence {
  std::string label;
  std::vector<double> onsets_s;
  bool fitted = true;  // false: fewer impacts than a fit takes, so the fit left it out
};

// A sound the detector heard and did not count as a bounce, with its reason.
struct ViewedRejection {
  double time_s = 0;
  std::string reason;
};

// What the report draws of one input: the waveform of the analysed channel and the detector's
// decisions on it.
struct RecordingView {
  std::filesystem::path input;  // as given on the command line
  std::filesystem::path audio;  // the recording drawn; empty when there is none
  int channel = 0;
  double duration_s = 0;
  std::optional<WaveformColumns> waveform;  // unset: `note` says why
  std::string note;
  std::vector<ViewedSequence> sequences;
  std::vector<ViewedRejection> rejected;
  bool HasEvents() const { return !sequences.empty() || !rejected.empty(); }
};

struct RecordingViewOptions {
  // The options the calibration loaded its inputs with: recordings are detected again with them,
  // so the figure shows exactly the impacts the fit used.
  calibrate::SequenceInputOptions input;
  double high_pass_hz = 300;  // display filter, as analyze --plot (its --band-low-hz default)
  int columns = 910;          // the figure's plot width in pixels: one column per pixel
};

// One view per input: a recording is detected again (its impacts, rejected events and sequences)
// and decimated; an analyze --json file gives its events and, when the recording it names is still
// there (as written, or beside the JSON), the waveform; an impact-time CSV gives nothing to draw.
// Throws InputError like the calibration's own loading.
std::vector<RecordingView> ViewRecordings(const std::vector<std::filesystem::path>& inputs,
                                          const RecordingViewOptions& options);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_REPORT_RECORDINGS_H_
