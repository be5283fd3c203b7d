#include "report_recordings.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>
#include <system_error>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/calibrate/impact_times.h"
#include "bouncecal/error.h"
#include "display_waveform.h"

namespace bouncecal::apps {
namespace {

std::string Label(const std::filesystem::path& file, std::size_t index) {
  // As calibrate::LoadSequences names the sequences, so the figure and the fit agree.
  return file.filename().string() + "#" + std::to_string(index + 1);
}

RecordingView FromRecording(const std::filesystem::path& input,
                            const RecordingViewOptions& options) {
  const auto& in = options.input;
  const auto analysis = audio::AnalyzeBounces(input, {in.detection, in.sequences});
  RecordingView view;
  view.input = input;
  view.audio = input;
  view.channel = analysis.detection.channel;
  view.duration_s = analysis.detection.duration_s;
  const auto& impacts = analysis.detection.detection.impacts;
  for (std::size_t s = 0; s < analysis.grouping.sequences.size(); ++s) {
    ViewedSequence sequence;
    sequence.label = Label(input, s);
    for (int index : analysis.grouping.sequences[s].impact_indices)
      sequence.onsets_s.push_back(impacts[static_cast<std::size_t>(index)].onset_s);
    sequence.fitted = static_cast<int>(sequence.onsets_s.size()) >= in.impact_times.min_impacts;
    view.sequences.push_back(std::move(sequence));
  }
  // As bouncecal analyze lists them: impacts left out of every sequence, and the rises the
  // detector merged into an impact (precursors, echoes).
  for (const auto& event : analysis.grouping.rejected)
    view.rejected.push_back({event.time_s, event.reason});
  for (const auto& merged : analysis.detection.detection.merged)
    view.rejected.push_back({merged.time_s, merged.reason});
  std::stable_sort(view.rejected.begin(), view.rejected.end(),
                   [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
  view.waveform = DisplayWaveform(input, view.channel, options.high_pass_hz, options.columns);
  return view;
}

// The recording an analyze entry names: as written (relative to where analyze ran), else beside
// the JSON file (a folder moved as a whole).
std::filesystem::path FindRecording(const std::filesystem::path& json,
                                    const std::filesystem::path& named) {
  std::error_code error;
  if (std::filesystem::is_regular_file(named, error)) return named;
  const auto beside = json.parent_path() / named.filename();
  if (std::filesystem::is_regular_file(beside, error)) return beside;
  return {};
}

// The per-recording entries of analyze output: "recordings" of bouncecal-analysis/1, or the
// shapes written before it (one entry, or an array of entries and a summary). The calibration
// has read the file already, so its format is known to be one of these.
std::vector<nlohmann::json> AnalyzeEntries(const nlohmann::json& document) {
  std::vector<nlohmann::json> entries;
  const nlohmann::json& list =
      document.is_object() && document.contains("recordings") ? document["recordings"] : document;
  if (list.is_array()) {
    for (const auto& item : list) {
      if (item.is_object() && item.contains("sequences")) entries.push_back(item);
    }
  } else if (list.is_object() && list.contains("sequences")) {
    entries.push_back(list);
  }
  return entries;
}

std::vector<RecordingView> FromAnalyzeJson(const std::filesystem::path& input,
                                           const RecordingViewOptions& options) {
  std::ifstream stream(input);
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(fmt::format("'{}' is not valid JSON ({})", input.string(), error.what()));
  }
  std::vector<RecordingView> views;
  try {
    for (const auto& entry : AnalyzeEntries(document)) {
      RecordingView view;
      view.input = input;
      const std::filesystem::path named = entry.value("file", std::string());
      view.channel = entry.value("channel", 0);
      view.duration_s = entry.value("duration_s", 0.0);
      const auto& sequences = entry.at("sequences");
      for (std::size_t s = 0; s < sequences.size(); ++s) {
        ViewedSequence sequence;
        sequence.label = Label(named.empty() ? input : named, s);
        sequence.onsets_s = sequences[s].at("onsets_s").get<std::vector<double>>();
        sequence.fitted =
            static_cast<int>(sequence.onsets_s.size()) >= options.input.impact_times.min_impacts;
        view.sequences.push_back(std::move(sequence));
      }
      for (const auto& event : entry.value("rejected_events", nlohmann::json::array())) {
        view.rejected.push_back(
            {event.at("time_s").get<double>(), event.value("reason", std::string())});
      }
      view.audio = named.empty() ? std::filesystem::path() : FindRecording(input, named);
      if (view.audio.empty()) {
        view.note = fmt::format(
            "The recording {} named in {} was not found (as written, or beside the JSON): the "
            "impacts and rejected events are drawn without the waveform.",
            named.empty() ? std::string("(none)") : named.string(), input.filename().string());
      } else {
        view.waveform =
            DisplayWaveform(view.audio, view.channel, options.high_pass_hz, options.columns);
      }
      views.push_back(std::move(view));
    }
  } catch (const nlohmann::json::exception& error) {
    throw InputError(
        fmt::format("'{}' does not have the shape bouncecal analyze --json writes ({})",
                    input.string(), error.what()));
  }
  return views;
}

}  // namespace

std::vector<RecordingView> ViewRecordings(const std::vector<std::filesystem::path>& inputs,
                                          const RecordingViewOptions& options) {
  std::vector<RecordingView> views;
  for (const auto& input : inputs) {
    std::string extension = input.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".json") {
      auto from_json = FromAnalyzeJson(input, options);
      views.insert(views.end(), from_json.begin(), from_json.end());
    } else if (calibrate::IsImpactTimesFile(input)) {
      RecordingView view;
      view.input = input;
      view.note = "An impact-time CSV: there is no recording to draw.";
      views.push_back(std::move(view));
    } else {
      views.push_back(FromRecording(input, options));
    }
  }
  return views;
}

}  // namespace bouncecal::apps
