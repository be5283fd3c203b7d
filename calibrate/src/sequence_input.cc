#include "bouncecal/calibrate/sequence_input.h"

#include "bouncecal/error.h"

namespace bouncecal::calibrate {

std::vector<MeasuredSequence> LoadSequences(const std::vector<std::filesystem::path>& inputs,
                                            const SequenceInputOptions& options) {
  std::vector<MeasuredSequence> sequences;
  for (const auto& input : inputs) {
    if (!std::filesystem::exists(input)) {
      throw InputError("input '" + input.string() + "' does not exist; check the path");
    }
    if (!IsImpactTimesFile(input)) {
      throw InputError("'" + input.string() + "': reading recordings needs the audio stage, " +
                       "which this build lacks; give an impact-time .csv or analyze .json");
    }
    auto read = ReadImpactTimes(input, options.impact_times);
    sequences.insert(sequences.end(), read.begin(), read.end());
  }
  return sequences;
}

}  // namespace bouncecal::calibrate
