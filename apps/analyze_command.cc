#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analyze_plot.h"
#include "bouncecal/calibrate/drop_height_check.h"
#include "bouncecal/calibrate/recording_analysis.h"
#include "bouncecal/calibrate/recording_manifest.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "option_alias.h"
#include "option_names.h"
#include "output_target.h"
#include "plot/gnuplot_plot.h"

namespace bouncecal::apps {
namespace {

struct AnalyzeArgs {
  std::vector<std::filesystem::path> recordings;
  std::filesystem::path manifest;
  std::vector<double> drop_heights_m;
  std::vector<double> drop_height_uncertainties_m;
  calibrate::RecordingAnalysisOptions analysis;
  std::filesystem::path json_path;
  std::filesystem::path csv_path;
  std::string plot_path;
};

using calibrate::RecordingAnalysis;

void PrintTable(std::FILE* out, const RecordingAnalysis& analysis) {
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
  // Which timing the onsets have: a user comparing runs (or a WAV with its phone copy) needs to
  // know whether the first lobe or the whole response timed them.
  const int timed_from_response = d.response_timing ? d.response_timing->own_sigma : 0;
  fmt::print(
      out, "  {} in {}, {}{}\n", d.info.codec, d.info.container,
      d.info.lossy ? "lossy" : "lossless",
      d.codec_timing
          ? fmt::format(
                ": onset uncertainties include +-{:.0f} us of codec timing{}",
                d.codec_timing->onset_uncertainty_s * 1e6,
                timed_from_response > 0 ? " except where timed from the impact's response" : "")
      : timed_from_response > 0
          ? fmt::format("; {} onsets timed from their impact's whole response", timed_from_response)
          : std::string());
  fmt::print(out, "  {} impacts, {} sequence(s), {} rejected events\n", d.detection.impacts.size(),
             analysis.sequences.size(), analysis.rejected.size());
  for (size_t s = 0; s < analysis.sequences.size(); ++s) {
    const auto& entry = analysis.sequences[s];
    const auto& p = entry.physics;
    fmt::print(out, "  sequence {}: {} impacts from {:.4f} s to {:.4f} s; ends: {}\n", s,
               entry.onsets.size(), entry.onsets.front().onset_s, entry.onsets.back().onset_s,
               entry.sequence.end_reason);
    fmt::print(out, "    {:>3} {:>10} {:>7} {:>2} {:>9} {:>7} {:>7} {:>7} {:>7} {:>9}\n", "k",
               "onset_s", "+-us", "", "dt_s", "e", "+-", "eta", "+-", "h_m");
    bool marked = false;
    for (size_t k = 0; k < entry.onsets.size(); ++k) {
      // How the onset was found and timed, as the JSON's residual_only and timed_from_response
      // say: why one onset is stated to 10 us and the next to 1.8 ms.
      std::string how;
      const auto& members = entry.sequence.impact_indices;
      if (k < members.size()) {
        const auto& impact = d.detection.impacts[static_cast<size_t>(members[k])];
        how =
            std::string(impact.residual_only ? "r" : "") + (impact.timed_from_response ? "a" : "");
      }
      marked = marked || !how.empty();
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
      fmt::print(out, "    {:>3} {:10.6f} {:7.1f} {:<2} {:>9} {:>7} {:>7} {:>7} {:>7} {:>9}\n",
                 k + 1, entry.onsets[k].onset_s, entry.onsets[k].uncertainty_s * 1e6, how, dt, e,
                 de, eta, deta, h);
    }
    if (marked) {
      fmt::print(out,
                 "    (r: heard only in earlier impacts' ringing, weak evidence; a: timed from its "
                 "whole response)\n");
    }
    if (p.energy_loss_mean_first_n) {
      fmt::print(out, "    mean energy loss over the first {} impacts: {:.4f} +- {:.2g}\n",
                 analysis.first_n, *p.energy_loss_mean_first_n,
                 *p.energy_loss_mean_first_n_uncertainty);
    } else {
      fmt::print(out, "    mean energy loss over the first {} impacts: n/a (fewer e values)\n",
                 analysis.first_n);
    }
  }
  for (const auto& event : analysis.rejected) {
    fmt::print(out, "  rejected {:10.6f} s: {}\n", event.time_s, event.reason);
  }
}

std::vector<AnalyzedRecording> ForPlot(const std::vector<RecordingAnalysis>& analyses) {
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
                 "bouncecal: warning: %s: lossy %s (%s): every onset uncertainty not timed from "
                 "the impact's response widened by %.0f us in quadrature (%s; docs/codecs.md); "
                 "record WAV or FLAC for the full precision\n",
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

// What the user should act on about one recording's sequences, one line each.
void WarnAboutSequences(const std::string& path, const RecordingAnalysis& analysis) {
  for (std::size_t s = 0; s < analysis.sequences.size(); ++s) {
    const auto& entry = analysis.sequences[s];
    if (entry.sequence.short_sequence) {
      std::fprintf(stderr,
                   "bouncecal: warning: %s: sequence %zu has only %zu impacts (a lossy ball, or "
                   "two or three sounds that time like bounces by chance); check them in the "
                   "table%s\n",
                   path.c_str(), s, entry.onsets.size(),
                   analysis.drop_height_m ? "" : ", and give --drop-height-m to time the first");
    }
    if (entry.height_check && !entry.height_check->consistent) {
      const std::string source =
          analysis.sequences.size() > 1 ? fmt::format("{} sequence {}", path, s) : path;
      fmt::print(stderr, "bouncecal: warning: {}\n",
                 WithFlags(calibrate::DescribeInconsistentDropHeight(source, *entry.height_check),
                           {"drop_height_m"}));
    }
  }
  if (const auto& periodic = analysis.grouping.periodic_events) {
    fmt::print(stderr,
               "bouncecal: warning: {}: {} of {} impacts repeat every {:.2f} ms ({:.1f} Hz: mains "
               "hum, a motor, a ticking clock); no chain along them is taken for bounces, and "
               "bounces they hide are lost: silence the source and record again\n",
               path, periodic->impacts_on_lattice, analysis.detection.detection.impacts.size(),
               1e3 * periodic->period_s, 1.0 / periodic->period_s);
  }
  // Most impacts left out of every sequence: the sequences may rest on a few of many knocks (a
  // noisy room, another source), worth a look before trusting them. Echoes and precursors merged
  // into an impact are part of it, not rejected knocks, so they do not count.
  std::size_t in_sequences = 0;
  for (const auto& entry : analysis.sequences) in_sequences += entry.onsets.size();
  const std::size_t left_out = analysis.grouping.rejected.size();
  if (left_out > in_sequences && left_out >= 4) {
    fmt::print(stderr,
               "bouncecal: warning: {}: {} of {} impacts fit no bounce sequence (listed under the "
               "table as rejected); check the recording with --plot before trusting its "
               "sequences\n",
               path, left_out, left_out + in_sequences);
  }
}

void Run(const AnalyzeArgs& args) {
  const TextOutputs text({{"--json", &args.json_path}, {"--csv", &args.csv_path}});
  std::FILE* out = text.human();
  args.analysis.Validate();
  const auto plan = calibrate::PlanRecordings(args.recordings, args.drop_heights_m,
                                              args.drop_height_uncertainties_m, args.manifest);
  if (!args.plot_path.empty()) CheckPlotTarget(args.plot_path);
  // Every file is analysed before any output is written, so a bad file leaves no output.
  std::vector<RecordingAnalysis> analyses;
  for (const auto& entry : plan) {
    // A manifest's ball column is calibrate's: intervals, e and eta do not depend on the ball.
    auto options = args.analysis;
    options.drop_height_m = entry.drop_height_m;
    options.drop_height_uncertainty_m = entry.drop_height_uncertainty_m.value_or(0.0);
    analyses.push_back(calibrate::AnalyzeRecording(entry.recording, options));
  }
  for (std::size_t i = 0; i < analyses.size(); ++i) {
    const std::string path = plan[i].recording.string();
    if (i) fmt::print(out, "\n");
    PrintTable(out, analyses[i]);
    if (analyses[i].detection.detection.impacts.empty()) {
      std::fprintf(stderr, "bouncecal: note: %s: no impacts found (silence or noise only)\n",
                   path.c_str());
    } else if (analyses[i].sequences.empty()) {
      std::fprintf(stderr, "bouncecal: note: %s: no bounce sequence among %zu impacts\n",
                   path.c_str(), analyses[i].detection.detection.impacts.size());
    }
    WarnAboutCodec(path, analyses[i].detection);
    WarnAboutSequences(path, analyses[i]);
  }
  if (analyses.size() > 1) {
    const auto summary = calibrate::AnalysisSummaryJson(analyses);
    if (summary["energy_loss_mean"].is_number()) {
      fmt::print(out, "\nacross {} recordings: mean energy loss (first {}) = {:.4f} +- {}\n",
                 summary["recordings_with_energy_loss"].get<size_t>(), args.analysis.first_n,
                 summary["energy_loss_mean"].get<double>(),
                 summary["energy_loss_std"].is_number()
                     ? fmt::format("{:.4f} (sample std)", summary["energy_loss_std"].get<double>())
                     : std::string("n/a"));
    }
  }
  if (!args.json_path.empty()) {
    WriteTextOutput(args.json_path, calibrate::AnalysisDocument(analyses).dump(2) + "\n");
  }
  if (!args.csv_path.empty()) WriteTextOutput(args.csv_path, calibrate::AnalysisCsv(analyses));
  if (!args.plot_path.empty()) {
    PlotAnalysis(args.plot_path, ForPlot(analyses),
                 {.high_pass_hz = args.analysis.detector.band_low_hz});
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
  auto* recordings = command->add_option(
      "recordings", args->recordings,
      "Recordings (WAV, FLAC, OGG, MP3, M4A/AAC, WebM, ...; lossy ones get wider onset "
      "uncertainties)");
  auto* manifest = command->add_option(
      "--manifest", args->manifest,
      "CSV or JSON listing the recordings with their drop heights (columns recording, "
      "drop_height_m, drop_height_uncertainty_m; docs/calibration.md)");
  recordings->excludes(manifest);
  command->callback([args, recordings, manifest] {
    if (recordings->count() == 0 && manifest->count() == 0) {
      throw ConfigError("analyze needs recordings: give their paths or --manifest FILE");
    }
    Run(*args);
  });
  auto* height = command->add_option(
      "--drop-height-m", args->drop_heights_m,
      "Release height h0 in m; gives e and eta of the first impact too, and is checked against "
      "the later bounces. Once for all recordings, or once per recording in order");
  height->allow_extra_args(false);
  AddDeprecatedAlias(*command, height, "--drop-height", args->drop_heights_m);
  auto* height_sigma = command->add_option(
      "--drop-height-uncertainty-m", args->drop_height_uncertainties_m,
      "One-sigma uncertainty of --drop-height-m in m, in e_1's and eta_1's uncertainty; once "
      "for all or once per recording");
  height_sigma->allow_extra_args(false);
  auto& a = args->analysis;
  auto* gravity =
      command->add_option("--gravity-mps2", a.gravity_mps2, "Gravitational acceleration in m/s^2")
          ->capture_default_str();
  AddDeprecatedAlias(*command, gravity, "--gravity", a.gravity_mps2);
  command->add_option("--first", a.first_n, "Average eta over the first N impacts")
      ->capture_default_str();
  command->add_option("--channel", a.channel,
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
  auto& d = a.detector;
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
  auto& s = a.sequences;
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
}

}  // namespace bouncecal::apps
