// bouncecal.analyze: the recording -> impacts -> bounce sequences -> e_k, eta_k path of
// `bouncecal analyze` (calibrate/recording_analysis.h), returning what its --json writes for one
// recording.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "bouncecal/audio/load_recording.h"
#include "bouncecal/audio/recording.h"
#include "bouncecal/calibrate/impact_rows.h"
#include "bouncecal/calibrate/recording_analysis.h"
#include "bouncecal/error.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

audio::Recording RecordingFromArray(const py::handle samples, std::optional<double> rate_hz) {
  if (!rate_hz) {
    throw ConfigError(
        "sample_rate_hz is needed with an array of samples (a file states its own rate)");
  }
  const double rate = *rate_hz;
  if (!(rate >= audio::RecordingReader::kMinSampleRateHz &&
        rate <= audio::RecordingReader::kMaxSampleRateHz && rate == std::floor(rate))) {
    throw ConfigError("sample_rate_hz must be a whole number of Hz in " +
                      std::to_string(audio::RecordingReader::kMinSampleRateHz) + ".." +
                      std::to_string(audio::RecordingReader::kMaxSampleRateHz) + ", got " +
                      std::to_string(rate));
  }
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(samples);
  if (!array) {
    throw InputError("samples: not an array of numbers; give a 1-D numpy array of samples");
  }
  if (array.ndim() != 1) {
    throw InputError("samples: a " + std::to_string(array.ndim()) +
                     "-D array; give one channel as a 1-D array (e.g. samples[:, 0])");
  }
  audio::Recording recording;
  recording.sample_rate_hz = static_cast<int>(rate);
  recording.samples.assign(array.data(), array.data() + array.size());
  if (recording.samples.size() < 2) {
    throw InputError("samples: " + std::to_string(recording.samples.size()) +
                     " sample(s); a recording needs at least two");
  }
  const auto bad = std::find_if(recording.samples.begin(), recording.samples.end(),
                                [](float x) { return !std::isfinite(x); });
  if (bad != recording.samples.end()) {
    throw InputError("samples: sample " + std::to_string(bad - recording.samples.begin()) +
                     " is not a finite number; remove NaN and infinite values");
  }
  return recording;
}

// The analysis document's entry for one recording (calibrate::ToJson, what `bouncecal analyze
// --json` writes) as Python: an Analysis (a Result that also gives one row per impact) with the
// same fields; impacts and rejected events as Tables, and every per-impact array of a sequence a
// numpy array even when empty.
py::object ToPython(const calibrate::RecordingAnalysis& analysis) {
  const nlohmann::json json = calibrate::ToJson(analysis);
  py::object result = NewResult("Analysis");
  result.attr("update")(FromJson(json));
  result["impacts"] = TableFromRecords(json.at("impacts"),
                                       {"onset_s", "onset_uncertainty_s", "peak_dbfs", "rise_db",
                                        "ringing_novelty_db", "snr_db", "sequence"},
                                       {}, {"residual_only", "timed_from_response"});
  // An impact outside every sequence is NaN, so the column stays float64 even when none is.
  std::vector<double> sequence_of_impact;
  for (const auto& impact : json.at("impacts")) {
    const auto& sequence = impact.at("sequence");
    sequence_of_impact.push_back(sequence.is_null() ? std::numeric_limits<double>::quiet_NaN()
                                                    : sequence.get<double>());
  }
  result["impacts"]["sequence"] = FloatArray(sequence_of_impact);
  result["rejected_events"] = TableFromRecords(json.at("rejected_events"), {"time_s"}, {"reason"});
  py::list sequences = result["sequences"];
  const auto& sequence_json = json.at("sequences");
  for (std::size_t s = 0; s < sequence_json.size(); ++s) {
    py::object sequence = sequences[s];
    for (const auto& [key, value] : sequence_json[s].items()) {
      if (value.is_array() && value.empty()) {
        sequence[py::str(key)] = key == "restitution_impact_index"
                                     ? py::object(IntArray(std::vector<int>{}))
                                     : py::object(FloatArray({}));
      }
    }
  }
  return result;
}

// calibrate::ImpactRows of an analysis (its to_dict(), the document's shape) as dicts whose keys
// are the columns in the CSV's order; None where a row has no value.
py::list ImpactRowsToPython(py::handle analysis) {
  const auto rows = calibrate::ImpactRows(ToJson(analysis, "analysis"));
  py::list list;
  for (const auto& row : rows) {
    const auto optional_int = [](const std::optional<int>& value) {
      return value ? py::object(py::int_(*value)) : py::object(py::none());
    };
    const std::array<py::object, calibrate::kImpactRowColumns.size()> values = {
        row.file ? py::object(py::str(*row.file)) : py::object(py::none()),
        py::int_(row.channel),
        optional_int(row.sequence),
        optional_int(row.k),
        py::float_(row.onset_s),
        py::float_(row.onset_uncertainty_s),
        py::float_(row.incoming_flight_uncertainty_s),
        py::float_(row.peak_dbfs),
        OptionalFloat(row.interval_s),
        OptionalFloat(row.bounce_height_m),
        OptionalFloat(row.restitution),
        OptionalFloat(row.restitution_uncertainty),
        OptionalFloat(row.energy_loss),
        OptionalFloat(row.energy_loss_uncertainty),
        py::bool_(row.residual_only),
        py::bool_(row.timed_from_response)};
    py::dict dict;
    for (std::size_t c = 0; c < values.size(); ++c) {
      dict[py::str(std::string(calibrate::kImpactRowColumns[c]))] = values[c];
    }
    list.append(dict);
  }
  return list;
}

}  // namespace

void BindAnalyze(py::module_& module) {
  const audio::DetectorOptions detector;
  const audio::SequenceOptions sequences;
  module.def(
      "analyze",
      [](py::object recording, std::optional<double> drop_height_m,
         double drop_height_uncertainty_m, double gravity_mps2, int first_n,
         std::optional<int> channel, std::optional<double> sample_rate_hz, double band_low_hz,
         double band_high_hz, double rise_threshold_db, double rise_lookback_ms, double min_snr_db,
         double min_gap_ms, bool ringing_residual, double frame_ms, double max_interval_s,
         double min_ratio, double max_ratio, double ratio_step_tolerance,
         double chatter_interval_ms, int min_impacts, double max_chance_alignment) {
        calibrate::RecordingAnalysisOptions options;
        options.drop_height_m = drop_height_m;
        options.drop_height_uncertainty_m = drop_height_uncertainty_m;
        options.gravity_mps2 = gravity_mps2;
        options.first_n = first_n;
        options.channel = channel;
        auto& d = options.detector;
        d.band_low_hz = band_low_hz;
        d.band_high_hz = band_high_hz;
        d.rise_threshold_db = rise_threshold_db;
        d.rise_lookback_ms = rise_lookback_ms;
        d.min_snr_db = min_snr_db;
        d.min_gap_ms = min_gap_ms;
        d.ringing_residual = ringing_residual;
        d.frame_ms = frame_ms;
        auto& s = options.sequences;
        s.max_interval_s = max_interval_s;
        s.min_ratio = min_ratio;
        s.max_ratio = max_ratio;
        s.ratio_step_tolerance = ratio_step_tolerance;
        s.chatter_interval_ms = chatter_interval_ms;
        s.min_impacts = min_impacts;
        s.max_chance_alignment = max_chance_alignment;
        options.Validate();
        if (IsPathLike(recording)) {
          if (sample_rate_hz) {
            throw ConfigError(
                "sample_rate_hz is for an array of samples; a recording file states its own "
                "rate");
          }
          const auto path = ToPath(recording, "recording");
          calibrate::RecordingAnalysis analysis;
          {
            py::gil_scoped_release release;
            analysis = calibrate::AnalyzeRecording(path, options);
          }
          return ToPython(analysis);
        }
        if (channel) {
          throw ConfigError("channel is for a recording file; give an array of one channel");
        }
        const auto samples = RecordingFromArray(recording, sample_rate_hz);
        calibrate::RecordingAnalysis analysis;
        {
          py::gil_scoped_release release;
          analysis = calibrate::AnalyzeRecordingSamples(samples, options);
        }
        return ToPython(analysis);
      },
      py::arg("recording"), py::kw_only(), py::arg("drop_height_m") = py::none(),
      py::arg("drop_height_uncertainty_m") = 0.0, py::arg("gravity_mps2") = 9.81,
      py::arg("first_n") = 3, py::arg("channel") = py::none(),
      py::arg("sample_rate_hz") = py::none(), py::arg("band_low_hz") = detector.band_low_hz,
      py::arg("band_high_hz") = detector.band_high_hz,
      py::arg("rise_threshold_db") = detector.rise_threshold_db,
      py::arg("rise_lookback_ms") = detector.rise_lookback_ms,
      py::arg("min_snr_db") = detector.min_snr_db, py::arg("min_gap_ms") = detector.min_gap_ms,
      py::arg("ringing_residual") = detector.ringing_residual,
      py::arg("frame_ms") = detector.frame_ms, py::arg("max_interval_s") = sequences.max_interval_s,
      py::arg("min_ratio") = sequences.min_ratio, py::arg("max_ratio") = sequences.max_ratio,
      py::arg("ratio_step_tolerance") = sequences.ratio_step_tolerance,
      py::arg("chatter_interval_ms") = sequences.chatter_interval_ms,
      py::arg("min_impacts") = sequences.min_impacts,
      py::arg("max_chance_alignment") = sequences.max_chance_alignment,
      R"doc(Find the impacts in a recording, group them into bounce sequences and compute each
sequence's intervals, restitution e_k, energy loss eta_k = 1 - e_k^2 and bounce heights, with
their uncertainties: what `bouncecal analyze --json` writes for one recording.

recording: a path (WAV, FLAC, OGG, MP3, M4A/AAC, ...; a lossy one gets wider onset
    uncertainties, codec_timing_uncertainty_s) or a 1-D numpy array of samples (full scale +-1)
    with sample_rate_hz.
drop_height_m: release height h0; gives e and eta of the first impact too, and each sequence's
    drop_height_check says whether e_1 agrees with the later impacts.
drop_height_uncertainty_m: one-sigma uncertainty of drop_height_m, in e_1's uncertainty.
channel: 0-based channel of a file (default: the best impact-to-noise ratio).
The other keywords are the detector's and the sequence finder's options (DetectorOptions,
SequenceOptions in bouncecal/audio/*.h; docs/detector.md), with the same names and defaults.

Returns an Analysis (a Result: a dict whose keys read as attributes) with the JSON's fields;
impacts and rejected_events are Tables of numpy columns; records() and to_dataframe() give one
row per impact, as `bouncecal analyze --csv` does. Raises InputError for an unreadable
recording, ConfigError for an option out of range.)doc");

  py::tuple columns(calibrate::kImpactRowColumns.size());
  for (std::size_t c = 0; c < calibrate::kImpactRowColumns.size(); ++c) {
    columns[c] = py::str(std::string(calibrate::kImpactRowColumns[c]));
  }
  module.attr("_IMPACT_COLUMNS") = columns;
  module.def("_impact_rows", &ImpactRowsToPython, py::arg("analysis"),
             "One dict per impact of an analysis' to_dict(), with _IMPACT_COLUMNS: the rows of "
             "`bouncecal analyze --csv` (calibrate::ImpactRows).");
}

}  // namespace bouncecal::python
