#include "bouncecal/calibrate/impact_rows.h"

#include <cmath>
#include <cstddef>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// A number of the document, none for null: JSON has no NaN, so a quantity that was not measured
// is null there (and a NaN of a document still in memory is treated the same).
std::optional<double> Number(const nlohmann::json& value) {
  if (value.is_null()) return std::nullopt;
  const double number = value.get<double>();
  return std::isfinite(number) ? std::optional<double>(number) : std::nullopt;
}

// Every way the entry can fail to be an analysis, in one message that says what to give instead.
InputError NotAnAnalysis(const std::string& why) {
  return InputError("not an analysis of one recording (" + why +
                    "); give one recording's entry of an analysis document (docs/json.md)");
}

std::optional<double> Entry(const nlohmann::json& array, std::size_t index) {
  return index < array.size() ? Number(array[index]) : std::nullopt;
}

std::vector<ImpactRow> Rows(const nlohmann::json& recording) {
  const auto& file = recording.at("file");
  const int channel = recording.at("channel").get<int>();
  const auto& impacts = recording.at("impacts");
  const auto& sequences = recording.at("sequences");
  // Members of a sequence are its impacts in time order, as the impacts are listed: the n-th
  // impact naming sequence s is its n-th member.
  std::vector<std::size_t> members_seen(sequences.size(), 0);
  std::vector<ImpactRow> rows;
  rows.reserve(impacts.size());
  for (const auto& impact : impacts) {
    ImpactRow row;
    if (!file.is_null()) row.file = file.get<std::string>();
    row.channel = channel;
    row.onset_s = impact.at("onset_s").get<double>();
    row.onset_uncertainty_s = impact.at("onset_uncertainty_s").get<double>();
    row.peak_dbfs = impact.at("peak_dbfs").get<double>();
    row.residual_only = impact.at("residual_only").get<bool>();
    row.timed_from_response = impact.at("timed_from_response").get<bool>();
    const auto& sequence_number = impact.at("sequence");
    if (!sequence_number.is_null()) {
      const int s = sequence_number.get<int>();
      if (s < 0 || static_cast<std::size_t>(s) >= sequences.size()) {
        throw NotAnAnalysis("an impact names sequence " + std::to_string(s) + " of " +
                            std::to_string(sequences.size()));
      }
      const auto& sequence = sequences[static_cast<std::size_t>(s)];
      const std::size_t position = members_seen[static_cast<std::size_t>(s)]++;
      if (position >= sequence.at("onsets_s").size()) {
        throw NotAnAnalysis("sequence " + std::to_string(s) + " has " +
                            std::to_string(sequence.at("onsets_s").size()) +
                            " onsets but more impacts name it");
      }
      row.sequence = s;
      row.k = static_cast<int>(position) + 1;
      if (sequence.contains("incoming_flight_uncertainty_s")) {
        row.incoming_flight_uncertainty_s =
            Entry(sequence["incoming_flight_uncertainty_s"], position).value_or(0.0);
      }
      row.interval_s = Entry(sequence.at("intervals_s"), position);
      row.bounce_height_m = Entry(sequence.at("bounce_height_m"), position);
      const auto& with_e = sequence.at("restitution_impact_index");
      for (std::size_t j = 0; j < with_e.size(); ++j) {
        if (with_e[j].get<std::size_t>() != position) continue;
        row.restitution = Entry(sequence.at("restitution"), j);
        row.restitution_uncertainty = Entry(sequence.at("restitution_uncertainty"), j);
        row.energy_loss = Entry(sequence.at("energy_loss"), j);
        row.energy_loss_uncertainty = Entry(sequence.at("energy_loss_uncertainty"), j);
        break;
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

std::vector<ImpactRow> ImpactRows(const nlohmann::json& recording) {
  try {
    return Rows(recording);
  } catch (const nlohmann::json::exception& error) {
    // The document's own reader names the missing or mistyped field.
    throw NotAnAnalysis(error.what());
  }
}

}  // namespace bouncecal::calibrate
