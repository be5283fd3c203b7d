// bouncecal.analyze: the recording -> impacts -> bounce sequences -> e_k, eta_k path of
// `bouncecal analyze`, returning what its --json writes for one recording.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/error.h"
#include "python_values.h"

namespace bouncecal::python {

namespace py = pybind11;

namespace {

struct AnalyzeOptions {
  std::optional<double> drop_height_m;
  double gravity_mps2 = 9.81;
  int first_n = 3;
  std::optional<int> channel;
  audio::DetectorOptions detector;
  audio::SequenceOptions sequences;
};

// The checks `bouncecal analyze` makes before it reads anything, naming the keyword.
void Validate(const AnalyzeOptions& options) {
  if (options.first_n < 1) {
    throw ConfigError("first_n must be at least 1, got " + std::to_string(options.first_n));
  }
  if (!(options.gravity_mps2 > 0 && std::isfinite(options.gravity_mps2))) {
    throw ConfigError("gravity_mps2 must be a positive number of m/s^2, got " +
                      std::to_string(options.gravity_mps2));
  }
  if (options.drop_height_m &&
      !(*options.drop_height_m > 0 && std::isfinite(*options.drop_height_m))) {
    throw ConfigError("drop_height_m must be a positive number of metres, got " +
                      std::to_string(*options.drop_height_m));
  }
}

// What `bouncecal analyze` computes for one recording (apps/analyze_command.cc, AnalyzeFile).
struct Analysis {
  audio::FileDetection detection;
  audio::SequenceResult grouping;
  std::vector<std::vector<calibrate::TimedImpact>> onsets;  // per sequence
  std::vector<calibrate::RestitutionAnalysis> physics;      // per sequence
  std::vector<audio::RejectedEvent> rejected;  // grouping's and the detector's merges, by time
};

void AnalyzeSequences(Analysis& analysis, const AnalyzeOptions& options) {
  const auto& impacts = analysis.detection.detection.impacts;
  calibrate::RestitutionOptions physics_options;
  physics_options.gravity_mps2 = options.gravity_mps2;
  physics_options.drop_height_m = options.drop_height_m;
  physics_options.first_n = options.first_n;
  for (const auto& sequence : analysis.grouping.sequences) {
    std::vector<calibrate::TimedImpact> onsets;
    for (int index : sequence.impact_indices) {
      const auto& impact = impacts[static_cast<std::size_t>(index)];
      onsets.push_back({impact.onset_s, impact.onset_uncertainty_s});
    }
    analysis.physics.push_back(calibrate::AnalyzeRestitution(onsets, physics_options));
    analysis.onsets.push_back(std::move(onsets));
  }
  analysis.rejected = analysis.grouping.rejected;
  for (const auto& merged : analysis.detection.detection.merged) {
    analysis.rejected.push_back({merged.time_s, std::nullopt, merged.reason});
  }
  std::stable_sort(analysis.rejected.begin(), analysis.rejected.end(),
                   [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
}

audio::SequenceOptions SequenceOptionsFor(const AnalyzeOptions& options) {
  audio::SequenceOptions sequences = options.sequences;
  if (options.drop_height_m) {
    sequences.release_flight_s =
        calibrate::DropFlightTime(*options.drop_height_m, options.gravity_mps2);
  }
  return sequences;
}

Analysis AnalyzeFile(const std::filesystem::path& path, const AnalyzeOptions& options) {
  audio::BounceAnalysisOptions bounce_options;
  bounce_options.detection.channel = options.channel;
  bounce_options.detection.detector = options.detector;
  bounce_options.sequences = SequenceOptionsFor(options);
  auto bounces = audio::AnalyzeBounces(path, bounce_options);
  Analysis analysis;
  analysis.detection = std::move(bounces.detection);
  analysis.grouping = std::move(bounces.grouping);
  AnalyzeSequences(analysis, options);
  return analysis;
}

// Samples in memory: the same detector and grouping as for a file, on one channel.
Analysis AnalyzeSamples(audio::Recording recording, const AnalyzeOptions& options) {
  const audio::SequenceOptions sequences = SequenceOptionsFor(options);
  sequences.Validate();
  Analysis analysis;
  auto& detection = analysis.detection;
  detection.info.sample_rate_hz = recording.sample_rate_hz;
  detection.info.channel_count = 1;
  detection.info.header_frames = static_cast<std::int64_t>(recording.samples.size());
  detection.duration_s = recording.duration_s();
  detection.detection = audio::DetectImpacts(recording, options.detector);
  detection.channel_impact_to_noise_db = {detection.detection.impact_to_noise_db};
  analysis.grouping = audio::GroupBounces(detection.detection, sequences);
  AnalyzeSequences(analysis, options);
  return analysis;
}

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

py::object ImpactsTable(const Analysis& analysis) {
  const auto& impacts = analysis.detection.detection.impacts;
  std::vector<double> onset, sigma, peak, rise, novelty, snr, sequence;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    onset.push_back(impacts[i].onset_s);
    sigma.push_back(impacts[i].onset_uncertainty_s);
    peak.push_back(impacts[i].peak_dbfs);
    rise.push_back(impacts[i].rise_db);
    novelty.push_back(impacts[i].ringing_novelty_db);
    snr.push_back(impacts[i].snr_db);
    const auto& index = analysis.grouping.sequence_of_impact[i];
    sequence.push_back(index ? *index : std::numeric_limits<double>::quiet_NaN());
  }
  py::object table = NewResult("Table");
  table["onset_s"] = FloatArray(onset);
  table["onset_uncertainty_s"] = FloatArray(sigma);
  table["peak_dbfs"] = FloatArray(peak);
  table["rise_db"] = FloatArray(rise);
  table["ringing_novelty_db"] = FloatArray(novelty);
  table["snr_db"] = FloatArray(snr);
  table["sequence"] = FloatArray(sequence);
  return table;
}

py::object SequenceResult(const Analysis& analysis, std::size_t s, int first_n) {
  const auto& p = analysis.physics[s];
  std::vector<double> onsets, sigmas;
  for (const auto& onset : analysis.onsets[s]) {
    onsets.push_back(onset.onset_s);
    sigmas.push_back(onset.uncertainty_s);
  }
  const auto& sequence = analysis.grouping.sequences[s];
  py::object result = NewResult();
  result["onsets_s"] = FloatArray(onsets);
  result["onset_uncertainty_s"] = FloatArray(sigmas);
  result["intervals_s"] = FloatArray(p.intervals_s);
  result["interval_uncertainty_s"] = FloatArray(p.interval_uncertainty_s);
  result["restitution"] = FloatArray(p.restitution);
  result["restitution_uncertainty"] = FloatArray(p.restitution_uncertainty);
  result["energy_loss"] = FloatArray(p.energy_loss);
  result["energy_loss_uncertainty"] = FloatArray(p.energy_loss_uncertainty);
  result["restitution_impact_index"] = IntArray(p.impact_index);
  result["bounce_height_m"] = FloatArray(p.bounce_height_m);
  result["bounce_height_uncertainty_m"] = FloatArray(p.bounce_height_uncertainty_m);
  result["energy_loss_mean_first_n"] = OptionalFloat(p.energy_loss_mean_first_n);
  result["energy_loss_mean_first_n_uncertainty"] =
      OptionalFloat(p.energy_loss_mean_first_n_uncertainty);
  result["first_n"] = first_n;
  result["end_reason"] = sequence.end_reason;
  result["short_sequence"] = sequence.short_sequence;
  return result;
}

// The fields of `bouncecal analyze --json` for one recording, in its order.
py::object ToPython(const Analysis& analysis, const AnalyzeOptions& options, bool from_file) {
  const auto& detection = analysis.detection;
  py::object result = NewResult();
  result["file"] = from_file ? py::object(py::str(detection.info.path.string())) : py::none();
  result["sample_rate_hz"] = detection.info.sample_rate_hz;
  result["channel"] = detection.channel;
  result["channel_count"] = detection.info.channel_count;
  result["channel_chosen_automatically"] = detection.channel_chosen_automatically;
  result["channel_impact_to_noise_db"] = FloatArray(detection.channel_impact_to_noise_db);
  result["duration_s"] = detection.duration_s;
  // How the file was decoded; samples handed over as an array were not.
  const auto& info = detection.info;
  const auto name_or_none = [from_file](const std::string& name) {
    return from_file ? py::object(py::str(name)) : py::object(py::none());
  };
  result["decoder"] = name_or_none(info.decoder);
  result["container"] = name_or_none(info.container);
  result["codec"] = name_or_none(info.codec);
  result["lossy"] = info.lossy;
  result["bit_rate_bps"] = OptionalFloat(info.bit_rate_bps);
  result["encoder_delay"] = std::string(audio::ToString(info.encoder_delay));
  // Already inside every onset uncertainty (added in quadrature); 0 for lossless input.
  result["codec_timing_uncertainty_s"] =
      detection.codec_timing ? detection.codec_timing->onset_uncertainty_s : 0.0;
  result["impacts"] = ImpactsTable(analysis);
  std::vector<double> rejected_times;
  std::vector<std::string> rejected_reasons;
  for (const auto& event : analysis.rejected) {
    rejected_times.push_back(event.time_s);
    rejected_reasons.push_back(event.reason);
  }
  py::object rejected = NewResult("Table");
  rejected["time_s"] = FloatArray(rejected_times);
  rejected["reason"] = StringList(rejected_reasons);
  result["rejected_events"] = rejected;
  py::list sequences;
  for (std::size_t s = 0; s < analysis.physics.size(); ++s) {
    sequences.append(SequenceResult(analysis, s, options.first_n));
  }
  result["sequences"] = sequences;
  result["drop_height_m"] = OptionalFloat(options.drop_height_m);
  result["gravity_mps2"] = options.gravity_mps2;
  return result;
}

}  // namespace

void BindAnalyze(py::module_& module) {
  const audio::DetectorOptions detector;
  const audio::SequenceOptions sequences;
  module.def(
      "analyze",
      [](py::object recording, std::optional<double> drop_height_m, double gravity_mps2,
         int first_n, std::optional<int> channel, std::optional<double> sample_rate_hz,
         double band_low_hz, double band_high_hz, double rise_threshold_db, double rise_lookback_ms,
         double min_snr_db, double min_gap_ms, bool ringing_residual, double frame_ms,
         double max_interval_s, double min_ratio, double max_ratio, double ratio_step_tolerance,
         double chatter_interval_ms, int min_impacts, double max_chance_alignment) {
        AnalyzeOptions options;
        options.drop_height_m = drop_height_m;
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
        Validate(options);
        if (IsPathLike(recording)) {
          if (sample_rate_hz) {
            throw ConfigError(
                "sample_rate_hz is for an array of samples; a recording file states its own "
                "rate");
          }
          const auto path = ToPath(recording, "recording");
          Analysis analysis;
          {
            py::gil_scoped_release release;
            analysis = AnalyzeFile(path, options);
          }
          return ToPython(analysis, options, /*from_file=*/true);
        }
        if (channel) {
          throw ConfigError("channel is for a recording file; give an array of one channel");
        }
        auto samples = RecordingFromArray(recording, sample_rate_hz);
        Analysis analysis;
        {
          py::gil_scoped_release release;
          analysis = AnalyzeSamples(std::move(samples), options);
        }
        return ToPython(analysis, options, /*from_file=*/false);
      },
      py::arg("recording"), py::kw_only(), py::arg("drop_height_m") = py::none(),
      py::arg("gravity_mps2") = 9.81, py::arg("first_n") = 3, py::arg("channel") = py::none(),
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
drop_height_m: release height h0; gives e and eta of the first impact too.
channel: 0-based channel of a file (default: the best impact-to-noise ratio).
The other keywords are the detector's and the sequence finder's options (DetectorOptions,
SequenceOptions in bouncecal/audio/*.h; docs/detector.md), with the same names and defaults.

Returns a Result (a dict whose keys read as attributes) with the JSON's fields;
impacts and rejected_events are Tables of numpy columns. Raises InputError for an unreadable
recording, ConfigError for an option out of range.)doc");
}

}  // namespace bouncecal::python
