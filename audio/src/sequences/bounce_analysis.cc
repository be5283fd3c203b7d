#include "bouncecal/audio/bounce_analysis.h"

#include <optional>
#include <utility>
#include <vector>

#include "sequences/leading_sounds.h"
#include "sequences/merged_alternatives.h"
#include "sequences/tentative_extension.h"
#include "sequences/weak_member_doubt.h"

namespace bouncecal::audio {

SequenceResult GroupBounces(DetectionResult& detection, const SequenceOptions& options) {
  options.Validate();
  if (const auto& from_s = options.stream_end_transient_from_s) {
    // Never adopted either: a tentative rise there is as likely the cut's burst.
    std::erase_if(detection.tentative,
                  [&](const Impact& impact) { return impact.onset_s >= *from_s; });
  }
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
  DoubtLeadingFlightsOffTheLaterRatios(detection.impacts, grouping.sequences);
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
  // The decoder runs on to the end of the padded frame after the recording's cut, and the cut's
  // burst spreads over the frame before it (SequenceOptions::stream_end_transient_from_s).
  if (!sequences.stream_end_transient_from_s && analysis.detection.codec_timing &&
      analysis.detection.codec_timing->frame_s) {
    sequences.stream_end_transient_from_s =
        analysis.detection.duration_s - 2.0 * *analysis.detection.codec_timing->frame_s;
  }
  analysis.grouping = GroupBounces(analysis.detection.detection, sequences);
  return analysis;
}

}  // namespace bouncecal::audio
