#ifndef BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_
#define BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_

#include <filesystem>
#include <string>
#include <vector>

#include "bouncecal/calibrate/impact_times.h"

namespace bouncecal::calibrate {

struct SequenceInputOptions {
  ImpactTimesOptions impact_times;
};

// Bounce sequences from recordings (audio files through the audio stage) or impact-time files
// (.csv, or .json written by bouncecal analyze --json). Throws InputError naming the file.
std::vector<MeasuredSequence> LoadSequences(const std::vector<std::filesystem::path>& inputs,
                                            const SequenceInputOptions& options = {});

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_SEQUENCE_INPUT_H_
