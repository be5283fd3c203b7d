#ifndef BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_
#define BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/detect_file.h"
#include "bouncecal/calibrate/impact_times.h"

namespace bouncecal::calibrate {

struct SequenceInputOptions {
  ImpactTimesOptions impact_times;  // for .csv/.json inputs
  // For recordings: the audio stage's defaults (they work on the shared recordings untuned).
  audio::FileDetectionOptions detection;
  audio::SequenceOptions sequences;
};

// Bounce sequences from recordings (any audio file libsndfile reads: detect impacts, group them
// into bounce sequences, each onset with its own timing uncertainty) or impact-time files (.csv,
// or .json written by bouncecal analyze --json). A recording holding several drops gives one
// sequence per drop ("file#k"). Throws InputError naming the file when it cannot be read or holds
// no bounce sequence.
std::vector<MeasuredSequence> LoadSequences(const std::vector<std::filesystem::path>& inputs,
                                            const SequenceInputOptions& options = {});

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_
