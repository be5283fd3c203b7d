#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "analyze_plot.h"
#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "option_alias.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

// The format of --json (docs/json.md, docs/schema/analysis.schema.json).
constexpr const char* kAnalysisFormat = "bouncecal-analysis/1";

struct AnalyzeArgs {
  std::vector<std::string> recordings;
  std::optional<double> drop_height_m;
  double gravity_mps2 = 9.81;
  int first_n = 3;
  std::optional<int> channel;
  std::filesystem::path json_path;
  std::filesystem::path csv_path;
  std::string plot_path;
  audio::DetectorOptions detector;
  audio::SequenceOptions sequences;
};

struct SequenceAnalysis {
  audio::BounceSequence sequence;
  std::vector<calibrate::TimedImpact> onsets;
  calibrate::RestitutionAnalysis physics;
};

struct FileAnalysis {
  audio::FileDetection detection;
  audio::SequenceResult grouping;
  std::vector<SequenceAnalysis> sequences;
  std::vector<audio::RejectedEvent> rejected;  // grouping + detector merges, by time
};

FileAnalysis AnalyzeFile(const std::string& path, const AnalyzeArgs& args) {
  FileAnalysis analysis;
  audio::BounceAnalysisOptions options;
  options.detection.channel = args.channel;
  options.detection.detector = args.detector;
  options.sequences = args.sequences;
  if (args.drop_height_m) {
    options.sequences.release_flight_s =
        calibrate::DropFlightTime(*args.drop_height_m, args.gravity_mps2);
  }
  auto bounces = audio::AnalyzeBounces(path, options);
  analysis.detection = std::move(bounces.detection);
  analysis.grouping = std::move(bounces.grouping);
  const auto& impacts = analysis.detection.detection.impacts;
  calibrate::RestitutionOptions physics_options;
  physics_options.gravity_mps2 = args.gravity_mps2;
  physics_options.drop_height_m = args.drop_height_m;
  physics_options.first_n = args.first_n;
  for (const auto& sequence : analysis.grouping.sequences) {
    SequenceAnalysis entry;
    entry.sequence = sequence;
    for (int index : sequence.impact_indices) {
      const auto& impact = impacts[static_cast<size_t>(index)];
      entry.onsets.push_back({impact.onset_s, impact.onset_uncertainty_s});
    }
    entry.physics = calibrate::AnalyzeRestitution(entry.onsets, physics_options);
    analysis.sequences.push_back(std::move(entry));
  }
  analysis.rejected = analysis.grouping.rejected;
  for (const auto& merged : analysis.detection.detection.merged) {
    analysis.rejected.push_back({merged.time_s, std::nullopt, merged.reason});
  }
  std::stable_sort(analysis.rejected.begin(), analysis.rejected.end(),
                   [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
  return analysis;
}

nlohmann::json OptionalNumber(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// JSON has no NaN or infinity: a quantity that was not measured is null.
nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json ToJson(const FileAnalysis& analysis, const AnalyzeArgs& args) {
  const auto& detection = analysis.detection;
  nlohmann::json file;
  file["file"] = detection.info.path.string();
  file["sample_rate_hz"] = detection.info.sample_rate_hz;
  file["channel"] = detection.channel;
  file["channel_count"] = detection.info.channel_count;
  file["channel_chosen_automatically"] = detection.channel_chosen_automatically;
  nlohmann::json scores = nlohmann::json::array();
  for (double score : detection.channel_impact_to_noise_db) {
    scores.push_back(FiniteOrNull(score));
  }
  file["channel_impact_to_noise_db"] = scores;
  file["duration_s"] = detection.duration_s;
  file["decoder"] = detection.info.decoder;
  file["container"] = detection.info.container;
  file["codec"] = detection.info.codec;
  file["lossy"] = detection.info.lossy;
  file["bit_rate_bps"] = OptionalNumber(detection.info.bit_rate_bps);
  file["encoder_delay"] = std::string(audio::ToString(detection.info.encoder_delay));
  // Already inside every onset_uncertainty_s below (added in quadrature); 0 for lossless input.
  file["codec_timing_uncertainty_s"] =
      detection.codec_timing ? detection.codec_timing->onset_uncertainty_s : 0.0;
  nlohmann::json impacts = nlohmann::json::array();
  const auto& list = detection.detection.impacts;
  for (size_t i = 0; i < list.size(); ++i) {
    const auto& sequence = analysis.grouping.sequence_of_impact[i];
    impacts.push_back({{"onset_s", list[i].onset_s},
                       {"onset_uncertainty_s", list[i].onset_uncertainty_s},
                       {"peak_dbfs", list[i].peak_dbfs},
                       {"rise_db", FiniteOrNull(list[i].rise_db)},
                       {"ringing_novelty_db", FiniteOrNull(list[i].ringing_novelty_db)},
                       {"snr_db", list[i].snr_db},
                       {"sequence", sequence ? nlohmann::json(*sequence) : nlohmann::json()}});
  }
  file["impacts"] = impacts;
  nlohmann::json rejected = nlohmann::json::array();
  for (const auto& event : analysis.rejected) {
    rejected.push_back({{"time_s", event.time_s}, {"reason", event.reason}});
  }
  file["rejected_events"] = rejected;
  nlohmann::json sequences = nlohmann::json::array();
  for (const auto& entry : analysis.sequences) {
    const auto& p = entry.physics;
    nlohmann::json onsets = nlohmann::json::array(), sigmas = nlohmann::json::array();
    for (const auto& onset : entry.onsets) {
      onsets.push_back(onset.onset_s);
      sigmas.push_back(onset.uncertainty_s);
    }
    sequences.push_back({
        {"onsets_s", onsets},
        {"onset_uncertainty_s", sigmas},
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
        {"first_n", args.first_n},
        {"end_reason", entry.sequence.end_reason},
        {"short_sequence", entry.sequence.short_sequence},
    });
  }
  file["sequences"] = sequences;
  file["drop_height_m"] = OptionalNumber(args.drop_height_m);
  file["gravity_mps2"] = args.gravity_mps2;
  return file;
}

// Mean and sample standard deviation of the first sequence's eta-bar across recordings, as the
// paper averages its five drops.
nlohmann::json Summary(const std::vector<FileAnalysis>& analyses, int first_n) {
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

void PrintTable(std::FILE* out, const FileAnalysis& analysis, const AnalyzeArgs& args) {
  const auto& d = analysis.detection;
  std::string channel_note;
  if (d.channel_chosen_automatically) {
    channel_note = ", chosen for the best impact-to-noise ratio (";
    for (size_t c = 0; c < d.channel_impact_to_noise_db.size(); ++c) {
      // A dead input (digital silence) scores -inf; the JSON writes null, the report says so.
      const double score = d.channel_impact_to_noise_db[c];
      channel_note += fmt::format(
          "{}ch {}: {}", c ? ", " : "", c,
          std::isfinite(score) ? fmt::format("{:.1f} dB", score) : std::string("silent"));
    }
    channel_note += ")";
  }
  fmt::print(out, "{}\n  {} Hz, {:.3f} s, channel {} of {}{}\n", d.info.path.string(),
             d.info.sample_rate_hz, d.duration_s, d.channel, d.info.channel_count, channel_note);
  fmt::print(out, "  {} in {}, {}{}\n", d.info.codec, d.info.container,
             d.info.lossy ? "lossy" : "lossless",
             d.codec_timing
                 ? fmt::format(": onset uncertainties include +-{:.0f} us of codec timing",
                               d.codec_timing->onset_uncertainty_s * 1e6)
                 : std::string());
  fmt::print(out, "  {} impacts, {} sequence(s), {} rejected events\n", d.detection.impacts.size(),
             analysis.sequences.size(), analysis.rejected.size());
  for (size_t s = 0; s < analysis.sequences.size(); ++s) {
    const auto& entry = analysis.sequences[s];
    const auto& p = entry.physics;
    fmt::print(out, "  sequence {}: {} impacts from {:.4f} s to {:.4f} s; ends: {}\n", s,
               entry.onsets.size(), entry.onsets.front().onset_s, entry.onsets.back().onset_s,
               entry.sequence.end_reason);
    fmt::print(out, "    {:>3} {:>10} {:>7} {:>9} {:>7} {:>7} {:>7} {:>7} {:>9}\n", "k", "onset_s",
               "+-us", "dt_s", "e", "+-", "eta", "+-", "h_m");
    for (size_t k = 0; k < entry.onsets.size(); ++k) {
      std::string dt = k < p.intervals_s.size() ? fmt::format("{:9.5f}", p.intervals_s[k]) : "";
      std::string h =
          k < p.bounce_height_m.size() ? fmt::format("{:9.5f}", p.bounce_height_m[k]) : "";
      std::string e, de, eta, deta;
      for (size_t j = 0; j < p.impact_index.size(); ++j) {
        if (p.impact_index[j] == static_cast<int>(k)) {
          e = fmt::format("{:7.4f}", p.restitution[j]);
          de = fmt::format("{:7.4f}", p.restitution_uncertainty[j]);
          eta = fmt::format("{:7.4f}", p.energy_loss[j]);
          deta = fmt::format("{:7.4f}", p.energy_loss_uncertainty[j]);
        }
      }
      fmt::print(out, "    {:>3} {:10.6f} {:7.1f} {:>9} {:>7} {:>7} {:>7} {:>7} {:>9}\n", k + 1,
                 entry.onsets[k].onset_s, entry.onsets[k].uncertainty_s * 1e6, dt, e, de, eta, deta,
                 h);
    }
    if (p.energy_loss_mean_first_n) {
      fmt::print(out, "    mean energy loss over the first {} impacts: {:.4f} +- {:.2g}\n",
                 args.first_n, *p.energy_loss_mean_first_n,
                 *p.energy_loss_mean_first_n_uncertainty);
    } else {
      fmt::print(out, "    mean energy loss over the first {} impacts: n/a (fewer e values)\n",
                 args.first_n);
    }
  }
  for (const auto& event : analysis.rejected) {
    fmt::print(out, "  rejected {:10.6f} s: {}\n", event.time_s, event.reason);
  }
}

std::string Csv(const std::vector<FileAnalysis>& analyses) {
  std::string csv =
      "file,channel,sequence,k,onset_s,onset_uncertainty_s,peak_dbfs,interval_s,"
      "bounce_height_m,restitution,restitution_uncertainty,energy_loss,"
      "energy_loss_uncertainty\n";
  for (const auto& analysis : analyses) {
    const auto& impacts = analysis.detection.detection.impacts;
    for (size_t i = 0; i < impacts.size(); ++i) {
      const auto sequence = analysis.grouping.sequence_of_impact[i];
      std::string tail = ",,,,,,";
      std::string k;
      if (sequence) {
        const auto& entry = analysis.sequences[static_cast<size_t>(*sequence)];
        const auto& members = entry.sequence.impact_indices;
        const auto position = static_cast<size_t>(
            std::find(members.begin(), members.end(), static_cast<int>(i)) - members.begin());
        k = std::to_string(position + 1);
        const auto& p = entry.physics;
        std::string dt, h, e, de, eta, deta;
        if (position < p.intervals_s.size()) {
          dt = fmt::format("{:.9f}", p.intervals_s[position]);
          h = fmt::format("{:.9f}", p.bounce_height_m[position]);
        }
        for (size_t j = 0; j < p.impact_index.size(); ++j) {
          if (p.impact_index[j] == static_cast<int>(position)) {
            e = fmt::format("{:.6f}", p.restitution[j]);
            de = fmt::format("{:.6f}", p.restitution_uncertainty[j]);
            eta = fmt::format("{:.6f}", p.energy_loss[j]);
            deta = fmt::format("{:.6f}", p.energy_loss_uncertainty[j]);
          }
        }
        tail = fmt::format(",{},{},{},{},{},{}", dt, h, e, de, eta, deta);
      }
      std::string file = analysis.detection.info.path.string();
      if (file.find_first_of(",\"\n") != std::string::npos) {
        std::string quoted = "\"";
        for (char c : file) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
        file = quoted + "\"";
      }
      csv += fmt::format("{},{},{},{},{:.9f},{:.9f},{:.2f}{}\n", file, analysis.detection.channel,
                         sequence ? std::to_string(*sequence) : "", k, impacts[i].onset_s,
                         impacts[i].onset_uncertainty_s, impacts[i].peak_dbfs, tail);
    }
  }
  return csv;
}

std::vector<AnalyzedRecording> ForPlot(const std::vector<FileAnalysis>& analyses) {
  std::vector<AnalyzedRecording> recordings;
  for (const auto& analysis : analyses) {
    AnalyzedRecording recording;
    recording.path = analysis.detection.info.path;
    recording.channel = analysis.detection.channel;
    for (const auto& entry : analysis.sequences) {
      for (const auto& onset : entry.onsets) recording.impact_onsets_s.push_back(onset.onset_s);
      recording.sequences.push_back(entry.physics);
    }
    for (const auto& event : analysis.rejected) recording.rejected_times_s.push_back(event.time_s);
    recordings.push_back(std::move(recording));
  }
  return recordings;
}

// One line each: what a lossy codec does to the onsets, and an encoder delay the file does not
// state (a constant offset of every onset, which intervals, e and eta do not see).
void WarnAboutCodec(const std::string& path, const audio::FileDetection& detection) {
  const auto& info = detection.info;
  if (const auto& timing = detection.codec_timing) {
    const std::string rate = info.bit_rate_bps
                                 ? fmt::format("{:.0f} kbit/s", *info.bit_rate_bps / 1e3)
                                 : std::string("unknown bit rate");
    const std::string basis =
        !timing->measured
            ? std::string("not measured for this codec: the largest measured codec error")
        : timing->high_bit_rate_bps_per_channel > 0
            ? fmt::format("measured for {} {} {:.0f} kbit/s per channel", timing->family,
                          timing->high_bit_rate ? "at or above" : "below",
                          timing->high_bit_rate_bps_per_channel / 1e3)
            : fmt::format("measured for {}", timing->family);
    std::fprintf(stderr,
                 "bouncecal: warning: %s: lossy %s (%s): every onset uncertainty widened by %.0f "
                 "us in quadrature (%s; docs/codecs.md); record WAV or FLAC for the full "
                 "precision\n",
                 path.c_str(), info.codec.c_str(), rate.c_str(), timing->onset_uncertainty_s * 1e6,
                 basis.c_str());
  }
  if (info.encoder_delay == audio::EncoderDelay::kUnknown) {
    std::fprintf(stderr,
                 "bouncecal: warning: %s: the %s stream does not state its encoder delay, so "
                 "every onset time may be late by the same 20-50 ms; intervals, e and eta are "
                 "unaffected\n",
                 path.c_str(), info.codec.c_str());
  }
}

void Run(const AnalyzeArgs& args) {
  const TextOutputs text({{"--json", &args.json_path}, {"--csv", &args.csv_path}});
  std::FILE* out = text.human();
  if (args.first_n < 1)
    throw ConfigError("--first must be at least 1, got " + std::to_string(args.first_n));
  if (!(args.gravity_mps2 > 0)) throw ConfigError("--gravity-mps2 must be positive m/s^2");
  if (args.drop_height_m && !(*args.drop_height_m > 0)) {
    throw ConfigError("--drop-height-m must be a positive number of metres");
  }
  if (!args.plot_path.empty()) CheckPlotTarget(args.plot_path);
  // Every file is analysed before any output is written, so a bad file leaves no output.
  std::vector<FileAnalysis> analyses;
  for (const auto& path : args.recordings) analyses.push_back(AnalyzeFile(path, args));
  for (size_t i = 0; i < analyses.size(); ++i) {
    if (i) fmt::print(out, "\n");
    PrintTable(out, analyses[i], args);
    if (analyses[i].detection.detection.impacts.empty()) {
      std::fprintf(stderr, "bouncecal: note: %s: no impacts found (silence or noise only)\n",
                   args.recordings[i].c_str());
    } else if (analyses[i].sequences.empty()) {
      std::fprintf(stderr, "bouncecal: note: %s: no bounce sequence among %zu impacts\n",
                   args.recordings[i].c_str(), analyses[i].detection.detection.impacts.size());
    }
    WarnAboutCodec(args.recordings[i], analyses[i].detection);
    for (size_t s = 0; s < analyses[i].sequences.size(); ++s) {
      const auto& entry = analyses[i].sequences[s];
      if (!entry.sequence.short_sequence) continue;
      std::fprintf(stderr,
                   "bouncecal: warning: %s: sequence %zu has only %zu impacts (a lossy ball, or "
                   "two or three sounds that time like bounces by chance); check them in the "
                   "table%s\n",
                   args.recordings[i].c_str(), s, entry.onsets.size(),
                   args.drop_height_m ? "" : ", and give --drop-height-m to time the first");
    }
  }
  if (analyses.size() > 1) {
    const auto summary = Summary(analyses, args.first_n);
    if (summary["energy_loss_mean"].is_number()) {
      fmt::print(out, "\nacross {} recordings: mean energy loss (first {}) = {:.4f} +- {}\n",
                 summary["recordings_with_energy_loss"].get<size_t>(), args.first_n,
                 summary["energy_loss_mean"].get<double>(),
                 summary["energy_loss_std"].is_number()
                     ? fmt::format("{:.4f} (sample std)", summary["energy_loss_std"].get<double>())
                     : std::string("n/a"));
    }
  }
  if (!args.json_path.empty()) {
    // One shape for any number of recordings (docs/json.md): the format, one entry per recording
    // in the order given, and the summary across them.
    nlohmann::json recordings = nlohmann::json::array();
    for (const auto& analysis : analyses) recordings.push_back(ToJson(analysis, args));
    nlohmann::json json = {{"format", kAnalysisFormat},
                           {"recordings", recordings},
                           {"summary", Summary(analyses, args.first_n)}};
    // Deprecated, for one release like the old option spellings: a document of one recording
    // also carries that recording's fields at its top level, the shape written before the
    // format field, so the scripts and scorers that read `.impacts` / `.sequences` keep working
    // instead of silently finding nothing (docs/json.md).
    if (recordings.size() == 1) {
      for (const auto& [key, value] : recordings.front().items()) {
        if (!json.contains(key)) json[key] = value;
      }
    }
    WriteTextOutput(args.json_path, json.dump(2) + "\n");
  }
  if (!args.csv_path.empty()) WriteTextOutput(args.csv_path, Csv(analyses));
  if (!args.plot_path.empty()) {
    PlotAnalysis(args.plot_path, ForPlot(analyses), {.high_pass_hz = args.detector.band_low_hz});
    fmt::print(out, "plot written to {}\n", args.plot_path);
  }
}

}  // namespace

void AddAnalyzeCommand(CLI::App& app) {
  auto args = std::make_shared<AnalyzeArgs>();
  auto* command = app.add_subcommand(
      "analyze",
      "Find every impact in recordings of a bouncing ball, group them into bounce sequences and "
      "compute intervals, restitution e_k, energy loss eta_k = 1 - e_k^2 and bounce heights.");
  command->footer(
      "Example:\n"
      "  bouncecal analyze drop1.wav drop2.wav --drop-height-m 0.20 --json out.json --plot "
      "out.png\n"
      "  bouncecal analyze drop.wav --json - | jq '.recordings[0].sequences[0].energy_loss'\n"
      "--json writes {\"format\": \"bouncecal-analysis/1\", \"recordings\": [one object per "
      "file], \"summary\": {...}} for any number of recordings (docs/json.md); the summary has "
      "the mean and sample std of the first sequence's eta-bar.");
  command
      ->add_option("recordings", args->recordings,
                   "Recordings (WAV, FLAC, OGG, MP3, M4A/AAC, WebM, ...; lossy ones get wider "
                   "onset uncertainties)")
      ->required();
  auto* height = command->add_option("--drop-height-m", args->drop_height_m,
                                     "Release height h0 in m; gives e and eta of the first "
                                     "impact too");
  AddDeprecatedAlias(*command, height, "--drop-height", args->drop_height_m);
  auto* gravity =
      command
          ->add_option("--gravity-mps2", args->gravity_mps2, "Gravitational acceleration in m/s^2")
          ->capture_default_str();
  AddDeprecatedAlias(*command, gravity, "--gravity", args->gravity_mps2);
  command->add_option("--first", args->first_n, "Average eta over the first N impacts")
      ->capture_default_str();
  command->add_option("--channel", args->channel,
                      "0-based channel to analyse (default: the one with the best "
                      "impact-to-noise ratio)");
  command->add_option("--json", args->json_path,
                      "Write the results as JSON (bouncecal-analysis/1) to this file, - for "
                      "stdout");
  command->add_option("--csv", args->csv_path,
                      "Write one row per impact as CSV to this file, - for stdout");
  command->add_option("--plot", args->plot_path,
                      "Plot the waveform with impacts and rejected events marked, and eta_k vs k "
                      "(.png or .svg)");
  auto& d = args->detector;
  command->add_option("--band-low-hz", d.band_low_hz, "Pre-filter high-pass edge in Hz")
      ->capture_default_str();
  command->add_option("--band-high-hz", d.band_high_hz, "Pre-filter low-pass edge in Hz (0 = none)")
      ->capture_default_str();
  command
      ->add_option("--rise-threshold-db", d.rise_threshold_db,
                   "Rise in dB above the preceding lookback that makes an impact")
      ->capture_default_str();
  command
      ->add_option("--rise-lookback-ms", d.rise_lookback_ms,
                   "Lookback in ms the rise is measured against")
      ->capture_default_str();
  command
      ->add_option("--min-snr-db", d.min_snr_db, "Minimum impact level above the noise floor in dB")
      ->capture_default_str();
  command
      ->add_option("--min-gap-ms", d.min_gap_ms,
                   "Rises closer than this (ms) are one impact (precursors, echoes)")
      ->capture_default_str();
  command->add_flag("!--no-ringing-residual", d.ringing_residual,
                    "Do not look for impacts buried in the ringing of earlier ones (faster)");
  auto& s = args->sequences;
  command
      ->add_option("--max-interval-s", s.max_interval_s,
                   "Longest flight in s that still belongs to one drop")
      ->capture_default_str();
  command
      ->add_option("--chatter-interval-ms", s.chatter_interval_ms,
                   "Flights shorter than this (ms) end a sequence as chatter")
      ->capture_default_str();
  command
      ->add_option("--max-chance-alignment", s.max_chance_alignment,
                   "Impacts found only in a ringing tail complete a sequence when chance would "
                   "line up events as well in fewer than this many of the chains searched "
                   "(0 = never)")
      ->capture_default_str();
  command->callback([args] { Run(*args); });
}

}  // namespace bouncecal::apps
