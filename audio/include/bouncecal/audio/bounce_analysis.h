#ifndef BOUNCECAL_AUDIO_BOUNCE_ANALYSIS_H_
#define BOUNCECAL_AUDIO_BOUNCE_ANALYSIS_H_

#include <filesystem>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/detect_file.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// The one path from a recording to its bounce sequences, shared by `bouncecal analyze`, the
// calibration input and the tests: detect impacts (detect_file.h), adopt the tentative ones
// where a bounce sequence predicts the next bounce (ExtendSequencesWithTentative), group the
// impacts into sequences (FindBounceSequences), and widen the stated onset uncertainty of
// residual-only members that miss where their sequence puts the bounce (docs/detector.md), all
// with the caller's sequence options.
struct BounceAnalysisOptions {
  FileDetectionOptions detection;
  SequenceOptions sequences;
};

struct BounceAnalysis {
  // Its impacts include the tentative impacts a sequence adopted (flagged residual_only).
  FileDetection detection;
  SequenceResult grouping;
};

// Throws InputError for an unreadable file and ConfigError for bad options.
BounceAnalysis AnalyzeBounces(const std::filesystem::path& path,
                              const BounceAnalysisOptions& options = {});

// The same for impacts already detected (a stream, a synthetic recording): moves the tentative
// impacts that continue a sequence into detection.impacts (and clears detection.tentative),
// then groups them, moves a member to a sound merged into it where that sound continues the
// sequence's interval ratios clearly better (src/sequences/merged_alternatives.h; its entry in
// detection.merged then records the onset given up), and widens the doubtful members'
// uncertainties in detection.impacts.
SequenceResult GroupBounces(DetectionResult& detection, const SequenceOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_BOUNCE_ANALYSIS_H_
