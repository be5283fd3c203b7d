#include "bouncecal/audio/bounce_analysis.h"

#include <utility>

namespace bouncecal::audio {

SequenceResult GroupBounces(DetectionResult& detection, const SequenceOptions& options) {
  options.Validate();
  if (!detection.tentative.empty() && !detection.impacts.empty()) {
    detection.impacts =
        ExtendSequencesWithTentative(detection.impacts, detection.tentative, options);
  }
  detection.tentative.clear();
  return FindBounceSequences(detection.impacts, options);
}

BounceAnalysis AnalyzeBounces(const std::filesystem::path& path,
                              const BounceAnalysisOptions& options) {
  options.sequences.Validate();
  BounceAnalysis analysis;
  analysis.detection = DetectImpactsInFile(path, options.detection);
  analysis.grouping = GroupBounces(analysis.detection.detection, options.sequences);
  return analysis;
}

}  // namespace bouncecal::audio
