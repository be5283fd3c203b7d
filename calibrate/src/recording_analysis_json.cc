// The analysis document (docs/json.md, docs/schema/analysis.schema.json) and the per-impact CSV,
// written once for `bouncecal analyze` and `bouncecal.analyze`.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "bouncecal/calibrate/impact_rows.h"
#include "bouncecal/calibrate/recording_analysis.h"

namespace bouncecal::calibrate {
namespace {

nlohmann::json OptionalNumber(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// JSON has no NaN or infinity: a quantity that was not measured is null.
nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// How a file was decoded; samples handed over in memory were not.
nlohmann::json FileText(const RecordingAnalysis& analysis, const std::string& text) {
  return analysis.from_file ? nlohmann::json(text) : nlohmann::json(nullptr);
}

nlohmann::json ToJson(const std::optional<DropHeightCheck>& check) {
  if (!check) return nullptr;
  return {{"consistent", check->consistent},
          {"first_restitution", check->first_restitution},
          {"first_restitution_uncertainty", check->first_restitution_uncertainty},
          {"later_impacts", check->later_impacts},
          {"later_restitution_mean", check->later_restitution_mean},
          {"later_restitution_min", check->later_restitution_min},
          {"later_restitution_max", check->later_restitution_max},
          {"deviation_sigma", check->deviation_sigma},
          {"implied_drop_height_m", check->implied_drop_height_m}};
}

nlohmann::json ToJson(const SequenceAnalysis& entry, const RecordingAnalysis& analysis) {
  const auto& p = entry.physics;
  nlohmann::json onsets = nlohmann::json::array(), sigmas = nlohmann::json::array(),
                 flight_sigmas = nlohmann::json::array();
  for (const auto& onset : entry.onsets) {
    onsets.push_back(onset.onset_s);
    sigmas.push_back(onset.uncertainty_s);
    flight_sigmas.push_back(onset.incoming_flight_uncertainty_s);
  }
  return {
      {"onsets_s", onsets},
      {"onset_uncertainty_s", sigmas},
      {"incoming_flight_uncertainty_s", flight_sigmas},
      {"intervals_s", p.intervals_s},
      {"interval_uncertainty_s", p.interval_uncertainty_s},
      {"restitution", p.restitution},
      {"restitution_uncertainty", p.restitution_uncertainty},
      {"energy_loss", p.energy_loss},
      {"energy_loss_uncertainty", p.energy_loss_uncertainty},
      {"restitution_impact_index", p.impact_index},
      {"bounce_height_m", p.bounce_height_m},
      {"bounce_height_uncertainty_m", p.bounce_height_uncertainty_m},
      {"energy_loss_mean_first_n", OptionalNumber(p.energy_loss_mean_first_n)},
      {"energy_loss_mean_first_n_uncertainty",
       OptionalNumber(p.energy_loss_mean_first_n_uncertainty)},
      {"first_n", analysis.first_n},
      {"end_reason", entry.sequence.end_reason},
      {"short_sequence", entry.sequence.short_sequence},
      {"drop_height_m", OptionalNumber(analysis.drop_height_m)},
      {"drop_height_check", ToJson(entry.height_check)},
  };
}

// A CSV cell: empty for what the row does not give.
std::string Fixed(const std::optional<double>& value, int decimals) {
  return value ? fmt::format("{:.{}f}", *value, decimals) : std::string();
}

std::string Optional(const std::optional<int>& value) {
  return value ? std::to_string(*value) : std::string();
}

std::string CsvField(std::string text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

nlohmann::json ToJson(const RecordingAnalysis& analysis) {
  const auto& detection = analysis.detection;
  const auto& info = detection.info;
  nlohmann::json file;
  file["file"] = FileText(analysis, info.path.string());
  file["sample_rate_hz"] = info.sample_rate_hz;
  file["channel"] = detection.channel;
  file["channel_count"] = info.channel_count;
  file["channel_chosen_automatically"] = detection.channel_chosen_automatically;
  nlohmann::json scores = nlohmann::json::array();
  for (double score : detection.channel_impact_to_noise_db) scores.push_back(FiniteOrNull(score));
  file["channel_impact_to_noise_db"] = scores;
  file["duration_s"] = detection.duration_s;
  file["decoder"] = FileText(analysis, info.decoder);
  file["container"] = FileText(analysis, info.container);
  file["codec"] = FileText(analysis, info.codec);
  file["lossy"] = info.lossy;
  file["bit_rate_bps"] = OptionalNumber(info.bit_rate_bps);
  file["encoder_delay"] = std::string(audio::ToString(info.encoder_delay));
  // Already inside every onset_uncertainty_s below not timed from the impact's response (added in
  // quadrature); 0 for lossless input.
  file["codec_timing_uncertainty_s"] =
      detection.codec_timing ? detection.codec_timing->onset_uncertainty_s : 0.0;
  nlohmann::json impacts = nlohmann::json::array();
  const auto& list = detection.detection.impacts;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& sequence = analysis.grouping.sequence_of_impact[i];
    impacts.push_back({{"onset_s", list[i].onset_s},
                       {"onset_uncertainty_s", list[i].onset_uncertainty_s},
                       {"peak_dbfs", list[i].peak_dbfs},
                       {"rise_db", FiniteOrNull(list[i].rise_db)},
                       {"ringing_novelty_db", FiniteOrNull(list[i].ringing_novelty_db)},
                       {"snr_db", list[i].snr_db},
                       {"residual_only", list[i].residual_only},
                       {"timed_from_response", list[i].timed_from_response},
                       {"sequence", sequence ? nlohmann::json(*sequence) : nlohmann::json()}});
  }
  file["impacts"] = impacts;
  nlohmann::json rejected = nlohmann::json::array();
  for (const auto& event : analysis.rejected) {
    rejected.push_back({{"time_s", event.time_s}, {"reason", event.reason}});
  }
  file["rejected_events"] = rejected;
  const auto& periodic = analysis.grouping.periodic_events;
  file["periodic_sound"] = periodic ? nlohmann::json{{"period_s", periodic->period_s},
                                                     {"impacts", periodic->impacts_on_lattice}}
                                    : nlohmann::json();
  nlohmann::json sequences = nlohmann::json::array();
  for (const auto& entry : analysis.sequences) sequences.push_back(ToJson(entry, analysis));
  file["sequences"] = sequences;
  file["drop_height_m"] = OptionalNumber(analysis.drop_height_m);
  file["drop_height_uncertainty_m"] = analysis.drop_height_uncertainty_m;
  file["gravity_mps2"] = analysis.gravity_mps2;
  return file;
}

nlohmann::json AnalysisSummaryJson(const std::vector<RecordingAnalysis>& analyses) {
  const int first_n = analyses.empty() ? 3 : analyses.front().first_n;
  std::vector<double> values;
  for (const auto& analysis : analyses) {
    if (!analysis.sequences.empty() && analysis.sequences[0].physics.energy_loss_mean_first_n) {
      values.push_back(*analysis.sequences[0].physics.energy_loss_mean_first_n);
    }
  }
  nlohmann::json summary = {{"recordings", analyses.size()},
                            {"recordings_with_energy_loss", values.size()},
                            {"first_n", first_n}};
  if (values.empty()) {
    summary["energy_loss_mean"] = nullptr;
    summary["energy_loss_std"] = nullptr;
    return summary;
  }
  double mean = 0;
  for (double v : values) mean += v / static_cast<double>(values.size());
  double variance = 0;
  for (double v : values) variance += (v - mean) * (v - mean);
  summary["energy_loss_mean"] = mean;
  summary["energy_loss_std"] =
      values.size() > 1
          ? nlohmann::json(std::sqrt(variance / static_cast<double>(values.size() - 1)))
          : nlohmann::json(nullptr);
  return summary;
}

nlohmann::json AnalysisDocument(const std::vector<RecordingAnalysis>& analyses) {
  nlohmann::json recordings = nlohmann::json::array();
  for (const auto& analysis : analyses) recordings.push_back(ToJson(analysis));
  nlohmann::json json = {{"format", kAnalysisFormat},
                         {"recordings", recordings},
                         {"summary", AnalysisSummaryJson(analyses)}};
  // Deprecated, for one release like the old option spellings: a document of one recording also
  // carries that recording's fields at its top level, the shape written before the format field,
  // so the scripts and scorers that read `.impacts` / `.sequences` keep working instead of
  // silently finding nothing (docs/json.md).
  if (recordings.size() == 1) {
    for (const auto& [key, value] : recordings.front().items()) {
      if (!json.contains(key)) json[key] = value;
    }
  }
  return json;
}

std::string AnalysisCsv(const std::vector<RecordingAnalysis>& analyses) {
  std::string csv;
  for (const auto column : kImpactRowColumns) {
    csv += csv.empty() ? "" : ",";
    csv += column;
  }
  csv += "\n";
  for (const auto& analysis : analyses) {
    for (const auto& row : ImpactRows(ToJson(analysis))) {
      csv += fmt::format(
          "{},{},{},{},{:.9f},{:.9f},{:.9f},{:.2f},{},{},{},{},{},{},{},{}\n",
          CsvField(row.file.value_or("")), row.channel, Optional(row.sequence), Optional(row.k),
          row.onset_s, row.onset_uncertainty_s, row.incoming_flight_uncertainty_s, row.peak_dbfs,
          Fixed(row.interval_s, 9), Fixed(row.bounce_height_m, 9), Fixed(row.restitution, 6),
          Fixed(row.restitution_uncertainty, 6), Fixed(row.energy_loss, 6),
          Fixed(row.energy_loss_uncertainty, 6), row.residual_only, row.timed_from_response);
    }
  }
  return csv;
}

}  // namespace bouncecal::calibrate
