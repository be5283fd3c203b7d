#include "bouncecal/calibrate/sequence_input.h"

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/calibrate/content_hash.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

std::vector<MeasuredSequence> FromRecording(const std::filesystem::path& path,
                                            const SequenceInputOptions& options) {
  const auto analysis = audio::AnalyzeBounces(path, {options.detection, options.sequences});
  const auto& impacts = analysis.detection.detection.impacts;
  const auto& grouping = analysis.grouping;
  std::vector<MeasuredSequence> sequences;
  for (size_t s = 0; s < grouping.sequences.size(); ++s) {
    MeasuredSequence sequence;
    sequence.source = path.filename().string() + "#" + std::to_string(s + 1);
    sequence.path = path;
    if (const auto& timing = analysis.detection.codec_timing) {
      sequence.lossy_codec = analysis.detection.info.codec;
      sequence.codec_timing_uncertainty_s = timing->onset_uncertainty_s;
    }
    for (int index : grouping.sequences[s].impact_indices) {
      const auto& impact = impacts[static_cast<size_t>(index)];
      sequence.impacts.push_back(
          {impact.onset_s, impact.onset_uncertainty_s, impact.incoming_flight_uncertainty_s});
    }
    if (static_cast<int>(sequence.impacts.size()) >= options.impact_times.min_impacts)
      sequences.push_back(std::move(sequence));
  }
  if (sequences.empty()) {
    throw InputError("'" + path.string() + "': found " + std::to_string(impacts.size()) +
                     " impacts but no bounce sequence of at least " +
                     std::to_string(options.impact_times.min_impacts) +
                     " impacts; check it with bouncecal analyze");
  }
  return sequences;
}

}  // namespace

std::vector<MeasuredSequence> LoadSequences(const std::vector<std::filesystem::path>& inputs,
                                            const SequenceInputOptions& options) {
  std::vector<MeasuredSequence> sequences;
  for (const auto& input : inputs) {
    if (!std::filesystem::exists(input)) {
      throw InputError("input '" + input.string() + "' does not exist; check the path");
    }
    auto read = IsImpactTimesFile(input) ? ReadImpactTimes(input, options.impact_times)
                                         : FromRecording(input, options);
    // Names the file in the duplicate warning of a fit (the same file given twice).
    const std::string hash = FileContentHash(input);
    for (auto& sequence : read) sequence.content_hash = hash;
    sequences.insert(sequences.end(), read.begin(), read.end());
  }
  return sequences;
}

}  // namespace bouncecal::calibrate
