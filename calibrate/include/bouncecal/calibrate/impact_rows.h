#ifndef BOUNCECAL_CALIBRATE_IMPACT_ROWS_H_
#define BOUNCECAL_CALIBRATE_IMPACT_ROWS_H_

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// An analysis as one row per detected impact: the rows of `bouncecal analyze --csv` and of
// `Analysis.records()` in Python, read from the analysis document's entry for one recording
// (recording_analysis.h's ToJson), so the table is a view of the one serialised result and both
// front ends show the same rows.
namespace bouncecal::calibrate {

struct ImpactRow {
  std::optional<std::string> file;  // none for samples handed over in memory
  int channel = 0;
  std::optional<int> sequence;  // 0-based; none for an impact in no sequence
  std::optional<int> k;         // 1-based place in the sequence, as eta_k is numbered
  double onset_s = 0;
  double onset_uncertainty_s = 0;
  // The sequence's own uncertainty of the flight that ends at this impact (TimedImpact); 0 for an
  // impact in no sequence or a document written before it was stated.
  double incoming_flight_uncertainty_s = 0;
  double peak_dbfs = 0;
  // What the sequence gives: the flight after this impact and the height it reached, m; e_k and
  // eta_k with their uncertainties. None where the sequence does not give them (no flight after
  // its last impact, no e_1 without a drop height).
  std::optional<double> interval_s;
  std::optional<double> bounce_height_m;
  std::optional<double> restitution;
  std::optional<double> restitution_uncertainty;
  std::optional<double> energy_loss;
  std::optional<double> energy_loss_uncertainty;
  bool residual_only = false;
  bool timed_from_response = false;
};

// The columns, in the order the CSV writes them and Python's rows hold them.
inline constexpr std::array<std::string_view, 16> kImpactRowColumns = {
    "file",
    "channel",
    "sequence",
    "k",
    "onset_s",
    "onset_uncertainty_s",
    "incoming_flight_uncertainty_s",
    "peak_dbfs",
    "interval_s",
    "bounce_height_m",
    "restitution",
    "restitution_uncertainty",
    "energy_loss",
    "energy_loss_uncertainty",
    "residual_only",
    "timed_from_response"};

// One row per entry of `recording`'s "impacts", in time order. Throws InputError when the entry
// lacks a field the rows need or an impact names a sequence it does not hold.
std::vector<ImpactRow> ImpactRows(const nlohmann::json& recording);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_IMPACT_ROWS_H_
