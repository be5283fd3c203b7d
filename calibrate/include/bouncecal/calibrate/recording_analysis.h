#ifndef BOUNCECAL_CALIBRATE_RECORDING_ANALYSIS_H_
#define BOUNCECAL_CALIBRATE_RECORDING_ANALYSIS_H_

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/recording.h"
#include "bouncecal/calibrate/drop_height_check.h"
#include "bouncecal/calibrate/restitution.h"

// The recording -> impacts -> bounce sequences -> e_k, eta_k path of `bouncecal analyze` and
// `bouncecal.analyze`, computed and serialised once for both (docs/json.md, "analysis").
namespace bouncecal::calibrate {

// The format of the analysis document (docs/json.md, docs/schema/analysis.schema.json).
inline constexpr std::string_view kAnalysisFormat = "bouncecal-analysis/1";

struct RecordingAnalysisOptions {
  // Release height h0 of the ball's lowest point, m. Gives e and eta of the first impact (the
  // paper's convention), tells the sequence finder when the first impact is due, and is checked
  // against the later impacts (drop_height_check.h). Unset: the experiment's geometry is not
  // assumed and the first impact has no e.
  std::optional<double> drop_height_m;
  // One-sigma uncertainty of drop_height_m, m; enters e_1's and eta_1's uncertainty.
  double drop_height_uncertainty_m = 0;
  double gravity_mps2 = 9.81;
  int first_n = 3;  // impacts averaged in energy_loss_mean_first_n
  // 0-based channel of a file; unset: the one whose impacts stand furthest above its noise.
  std::optional<int> channel;
  audio::DetectorOptions detector;
  audio::SequenceOptions sequences;

  // Throws OptionError naming the field (drop_height_m, first_n, ...) and its valid range.
  void Validate() const;
};

struct SequenceAnalysis {
  audio::BounceSequence sequence;
  std::vector<TimedImpact> onsets;
  RestitutionAnalysis physics;
  // With a drop height: whether e_1 agrees with the later impacts (drop_height_check.h).
  std::optional<DropHeightCheck> height_check;
};

struct RecordingAnalysis {
  audio::FileDetection detection;
  audio::SequenceResult grouping;
  std::vector<SequenceAnalysis> sequences;
  std::vector<audio::RejectedEvent> rejected;  // the grouping's and the detector's merges, by time
  // The settings the physics was computed with, so the result describes itself.
  std::optional<double> drop_height_m;
  double drop_height_uncertainty_m = 0;
  double gravity_mps2 = 9.81;
  int first_n = 3;
  // False for samples handed over in memory: file, decoder, container and codec are then null.
  bool from_file = true;
};

// Reads and analyses one recording. Throws InputError for an unreadable file, OptionError for
// bad options, and OptionError naming drop_height_m when a first rebound rose above it.
RecordingAnalysis AnalyzeRecording(const std::filesystem::path& path,
                                   const RecordingAnalysisOptions& options);
// The same for one channel of samples already in memory.
RecordingAnalysis AnalyzeRecordingSamples(const audio::Recording& recording,
                                          const RecordingAnalysisOptions& options);

// One recording's entry of the analysis document.
nlohmann::json ToJson(const RecordingAnalysis& analysis);
// Mean and sample standard deviation of the first sequence's eta-bar across recordings, as the
// paper averages its five drops.
nlohmann::json AnalysisSummaryJson(const std::vector<RecordingAnalysis>& analyses);
// The whole document: {"format", "recordings": [ToJson...], "summary"}; a document of one
// recording also carries that recording's fields at its top level (deprecated, docs/json.md).
nlohmann::json AnalysisDocument(const std::vector<RecordingAnalysis>& analyses);
// One row per impact, every recording (`analyze --csv`).
std::string AnalysisCsv(const std::vector<RecordingAnalysis>& analyses);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_RECORDING_ANALYSIS_H_
