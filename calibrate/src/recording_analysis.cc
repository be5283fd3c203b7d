#include "bouncecal/calibrate/recording_analysis.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/response_timing.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {
namespace {

audio::SequenceOptions SequenceOptionsFor(const RecordingAnalysisOptions& options) {
  audio::SequenceOptions sequences = options.sequences;
  // With a height the finder knows when the first impact is due after the release.
  if (options.drop_height_m) {
    sequences.release_flight_s = DropFlightTime(*options.drop_height_m, options.gravity_mps2);
  }
  return sequences;
}

std::string RecordingName(const RecordingAnalysis& analysis) {
  return analysis.from_file ? analysis.detection.info.path.string() : std::string("samples");
}

// Every sequence's intervals, e_k and eta_k, the drop height checked against them, and the
// rejected events in time order.
void AnalyzeSequences(RecordingAnalysis& analysis, const RecordingAnalysisOptions& options) {
  analysis.drop_height_m = options.drop_height_m;
  analysis.drop_height_uncertainty_m = options.drop_height_uncertainty_m;
  analysis.gravity_mps2 = options.gravity_mps2;
  analysis.first_n = options.first_n;
  const auto& impacts = analysis.detection.detection.impacts;
  RestitutionOptions physics_options;
  physics_options.gravity_mps2 = options.gravity_mps2;
  physics_options.drop_height_m = options.drop_height_m;
  physics_options.drop_height_uncertainty_m = options.drop_height_uncertainty_m;
  physics_options.first_n = options.first_n;
  const std::string name = RecordingName(analysis);
  for (std::size_t s = 0; s < analysis.grouping.sequences.size(); ++s) {
    const auto& sequence = analysis.grouping.sequences[s];
    SequenceAnalysis entry;
    entry.sequence = sequence;
    for (int index : sequence.impact_indices) {
      const auto& impact = impacts[static_cast<std::size_t>(index)];
      entry.onsets.push_back(
          {impact.onset_s, impact.onset_uncertainty_s, impact.incoming_flight_uncertainty_s});
    }
    entry.physics = AnalyzeRestitution(entry.onsets, physics_options);
    if (options.drop_height_m) {
      const std::string source =
          analysis.grouping.sequences.size() > 1 ? name + "#" + std::to_string(s + 1) : name;
      RefuseReboundAboveRelease(source, entry.physics, *options.drop_height_m);
      entry.height_check =
          CheckDropHeight(entry.physics, *options.drop_height_m, options.gravity_mps2);
    }
    analysis.sequences.push_back(std::move(entry));
  }
  analysis.rejected = analysis.grouping.rejected;
  for (const auto& merged : analysis.detection.detection.merged) {
    analysis.rejected.push_back({merged.time_s, std::nullopt, merged.reason});
  }
  std::stable_sort(analysis.rejected.begin(), analysis.rejected.end(),
                   [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
}

}  // namespace

void RecordingAnalysisOptions::Validate() const {
  if (first_n < 1) {
    throw OptionError({"first_n"}, "first_n must be at least 1, got " + std::to_string(first_n));
  }
  if (!(gravity_mps2 > 0 && std::isfinite(gravity_mps2))) {
    throw OptionError({"gravity_mps2"}, "gravity_mps2 must be a positive number of m/s^2, got " +
                                            std::to_string(gravity_mps2));
  }
  if (drop_height_m && !(*drop_height_m > 0 && std::isfinite(*drop_height_m))) {
    throw OptionError({"drop_height_m"}, "drop_height_m must be a positive number of metres, got " +
                                             std::to_string(*drop_height_m));
  }
  if (!(drop_height_uncertainty_m >= 0 && std::isfinite(drop_height_uncertainty_m))) {
    throw OptionError({"drop_height_uncertainty_m"},
                      "drop_height_uncertainty_m must be >= 0 m, got " +
                          std::to_string(drop_height_uncertainty_m));
  }
  if (drop_height_uncertainty_m > 0 && !drop_height_m) {
    throw OptionError({"drop_height_uncertainty_m", "drop_height_m"},
                      "drop_height_uncertainty_m needs drop_height_m (without a height nothing "
                      "depends on it)");
  }
}

RecordingAnalysis AnalyzeRecording(const std::filesystem::path& path,
                                   const RecordingAnalysisOptions& options) {
  options.Validate();
  audio::BounceAnalysisOptions bounce_options;
  bounce_options.detection.channel = options.channel;
  bounce_options.detection.detector = options.detector;
  bounce_options.sequences = SequenceOptionsFor(options);
  auto bounces = audio::AnalyzeBounces(path, bounce_options);
  RecordingAnalysis analysis;
  analysis.detection = std::move(bounces.detection);
  analysis.grouping = std::move(bounces.grouping);
  AnalyzeSequences(analysis, options);
  return analysis;
}

RecordingAnalysis AnalyzeRecordingSamples(const audio::Recording& recording,
                                          const RecordingAnalysisOptions& options) {
  options.Validate();
  const audio::SequenceOptions sequences = SequenceOptionsFor(options);
  sequences.Validate();
  RecordingAnalysis analysis;
  analysis.from_file = false;
  auto& detection = analysis.detection;
  detection.info.sample_rate_hz = recording.sample_rate_hz;
  detection.info.channel_count = 1;
  detection.info.header_frames = static_cast<std::int64_t>(recording.samples.size());
  detection.duration_s = recording.duration_s();
  detection.detection = audio::DetectImpacts(recording, options.detector);
  // As DetectImpactsInFile does, so samples in memory and the same samples in a WAV agree.
  detection.response_timing = audio::RetimeFromResponses(detection.detection, recording.samples, 0,
                                                         audio::ResponseTimingFor(detection.info));
  detection.channel_impact_to_noise_db = {detection.detection.impact_to_noise_db};
  analysis.grouping = audio::GroupBounces(detection.detection, sequences);
  AnalyzeSequences(analysis, options);
  return analysis;
}

}  // namespace bouncecal::calibrate
