#include "bouncecal/audio/bounce_analysis.h"

#include <optional>
#include <utility>

#include "sequences/merged_alternatives.h"
#include "sequences/tentative_extension.h"
#include "sequences/weak_member_doubt.h"

namespace bouncecal::audio {

SequenceResult GroupBounces(DetectionResult& detection, const SequenceOptions& options) {
  options.Validate();
  std::optional<SequenceResult> found;
  if (!detection.tentative.empty() && !detection.impacts.empty()) {
    TentativeExtension extension =
        ExtendWithTentative(detection.impacts, detection.tentative, options);
    detection.impacts = std::move(extension.impacts);
    found = std::move(extension.grouping);
  }
  detection.tentative.clear();
  SequenceResult grouping =
      found ? std::move(*found) : FindBounceSequences(detection.impacts, options);
  TakeMergedOnsetsThatFitTheSequence(detection.impacts, detection.merged, grouping.sequences);
  StateUnsearchedOnsetSpans(detection.impacts, grouping.sequences);
  StateDoubtOfWeakMembers(detection.impacts, grouping.sequences);
  return grouping;
}

BounceAnalysis AnalyzeBounces(const std::filesystem::path& path,
                              const BounceAnalysisOptions& options) {
  options.sequences.Validate();
  BounceAnalysis analysis;
  analysis.detection = DetectImpactsInFile(path, options.detection);
  // The reader knows the codec, so the chance test knows how densely it makes events.
  SequenceOptions sequences = options.sequences;
  if (!sequences.codec_frame_s && analysis.detection.codec_timing) {
    sequences.codec_frame_s = analysis.detection.codec_timing->frame_s;
  }
  analysis.grouping = GroupBounces(analysis.detection.detection, sequences);
  return analysis;
}

}  // namespace bouncecal::audio
