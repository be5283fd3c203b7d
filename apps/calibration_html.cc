#include "calibration_html.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "option_names.h"
#include "waveform_svg.h"

namespace bouncecal::apps {
namespace {

constexpr const char* kStyle = R"(
body { font-family: sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; border-bottom: 2px solid #446; padding-bottom: 0.2em; }
h2 { font-size: 1.25em; margin-top: 1.6em; color: #334; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.92em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: right; }
th { background: #eef; } td.text, th.text, table.facts td { text-align: left; }
code, pre { font-family: monospace; background: #f4f4f8; }
pre { padding: 0.6em; overflow-x: auto; font-size: 0.85em; }
.warning { color: #a00; font-weight: bold; }
figure { margin: 1em 0; } figure svg { max-width: 100%; height: auto; }
figcaption { font-size: 0.9em; color: #444; }
)";

std::string Number(double value, int digits = 6) {
  if (!std::isfinite(value)) return "n/a";
  return fmt::format("{:.{}g}", value, digits);
}

std::string Row(const std::vector<std::string>& cells, bool header = false) {
  std::string row = "<tr>";
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const char* tag = header ? "th" : "td";
    row += fmt::format("<{}{}>{}</{}>", tag, i == 0 ? " class=\"text\"" : "", cells[i], tag);
  }
  return row + "</tr>\n";
}

std::string InputsSection(const CalibrationReportContent& content) {
  std::string html = "<h2 id=\"inputs\">Inputs</h2>\n<table>\n";
  html += Row({"file", "content hash (FNV-1a 64)"}, true);
  for (const auto& recording : content.card.recordings) {
    html += Row({"<code>" + EscapeHtml(recording.file) + "</code>",
                 "<code>" + EscapeHtml(recording.content_hash) + "</code>"});
  }
  html += "</table>\n";
  const auto& options = content.options;
  const dem::Ball& ball = options.drop.ball;  // ReferenceBall() when not given
  html += fmt::format(
      "<p>Ball: {}d = {} m, m = {} kg; drop height {}; gravity {} m/s&sup2;; integrator "
      "{}{}.</p>\n",
      options.ball_preset.empty() ? "" : EscapeHtml(options.ball_preset) + ", ",
      Number(ball.diameter_m), Number(ball.MassKg(), 4),
      options.drop_height_given ? Number(options.drop.drop_height_m) + " m"
      : content.summary.sequences.empty() || !content.summary.sequences.front().drop_height_m
          ? std::string("not given (e_1 and eta_1 not computed; drops start from the first "
                        "measured bounce apex)")
          : std::string("per recording (below)"),
      Number(options.drop.gravity_mps2), dem::ToString(options.drop.integrator),
      options.drop.drag.enabled ? ", air drag on" : "");
  html += "<p>Command: <code>" + EscapeHtml(content.command_line) + "</code></p>\n";
  return html;
}

std::string RecordingsSection(const CalibrationReportContent& content) {
  std::string html =
      "<h2 id=\"waveforms\">Recordings: what was counted</h2>\n<p>Each recording's waveform "
      "(the analysed channel, high-passed at 300 Hz for display, lowest and highest sample per "
      "pixel column). <span style=\"color:#1f5fa8\">&#9660;</span> marks an impact of a bounce "
      "sequence, coloured by sequence, whose name and extent the bracket above shows; <span "
      "style=\"color:#c0392b\">&#10005;</span> marks a sound the detector rejected. Hover over a "
      "marker for its time and, for a rejected event, the reason; the reasons are also listed "
      "below each figure.</p>\n";
  for (const auto& view : content.recordings) {
    html += "<h3>" + EscapeHtml(view.input.filename().string()) + "</h3>\n";
    if (!view.audio.empty() && view.audio != view.input) {
      html += "<p>Recording: <code>" + EscapeHtml(view.audio.string()) + "</code></p>\n";
    }
    if (!view.note.empty()) html += "<p>" + EscapeHtml(view.note) + "</p>\n";
    if (!view.waveform && !view.HasEvents()) continue;
    std::size_t impacts = 0;
    for (const auto& sequence : view.sequences) impacts += sequence.onsets_s.size();
    html += "<figure>\n" + WaveformSvg(view) + "\n<figcaption>" +
            EscapeHtml(fmt::format("{}{}: {} impacts in {} sequence(s), {} rejected events.",
                                   view.audio.empty() ? view.input.filename().string()
                                                      : view.audio.filename().string(),
                                   view.waveform ? fmt::format(", channel {}", view.channel) : "",
                                   impacts, view.sequences.size(), view.rejected.size())) +
            "</figcaption>\n</figure>\n";
    if (view.rejected.empty()) continue;
    html += "<details class=\"rejected-events\"><summary>Rejected events and why (" +
            std::to_string(view.rejected.size()) + ")</summary>\n<table>\n";
    html += Row({"time (s)", "reason"}, true);
    for (const auto& event : view.rejected) {
      html += "<tr><td>" + fmt::format("{:.6f}", event.time_s) + "</td><td class=\"text\">" +
              EscapeHtml(event.reason) + "</td></tr>\n";
    }
    html += "</table></details>\n";
  }
  return html;
}

std::string ImpactsSection(const CalibrationReportContent& content) {
  std::string html = "<h2 id=\"impacts\">Impacts</h2>\n";
  for (const auto& sequence : content.summary.sequences) {
    const auto& measured = sequence.measured;
    html += "<h3>" + EscapeHtml(sequence.source) + "</h3>\n<table>\n";
    html += Row({"k", "flight dt_k (s)", "&plusmn; (s)", "bounce height (m)", "e_k", "&plusmn;",
                 "eta_k", "&plusmn;", "simulated eta_k"},
                true);
    // Row k describes impact k (1-based) and the flight after it.
    const std::size_t rows = measured.intervals_s.size() + 1;
    for (std::size_t k = 0; k < rows; ++k) {
      std::vector<std::string> cells(9);
      cells[0] = std::to_string(k + 1);
      if (k < measured.intervals_s.size()) {
        cells[1] = Number(measured.intervals_s[k]);
        cells[2] = Number(measured.interval_uncertainty_s[k], 2);
        cells[3] = Number(measured.bounce_height_m[k], 4);
      }
      for (std::size_t j = 0; j < measured.impact_index.size(); ++j) {
        if (measured.impact_index[j] != static_cast<int>(k)) continue;
        cells[4] = Number(measured.restitution[j], 4);
        cells[5] = Number(measured.restitution_uncertainty[j], 2);
        cells[6] = Number(measured.energy_loss[j], 4);
        cells[7] = Number(measured.energy_loss_uncertainty[j], 2);
      }
      for (std::size_t j = 0; j < sequence.simulated.impact_index.size(); ++j) {
        if (sequence.simulated.impact_index[j] != static_cast<int>(k)) continue;
        cells[8] = Number(sequence.simulated.energy_loss[j], 4);
      }
      html += Row(cells);
    }
    html += "</table>\n";
    if (measured.energy_loss_mean_first_n) {
      // Scatter and timing, as the uncertainty model combines them for the first N.
      const double timing = *measured.energy_loss_mean_first_n_uncertainty;
      const double scatter = content.summary.uncertainty.per_impact_scatter;
      const int first_n = sequence.first_n > 0 ? sequence.first_n : content.summary.first_n;
      html += fmt::format(
          "<p>Mean energy loss of the first {} impacts: {} &plusmn; {} (timing alone &plusmn; "
          "{}; per-impact scatter sd {})</p>\n",
          first_n, Number(*measured.energy_loss_mean_first_n, 4),
          Number(std::sqrt(scatter * scatter / first_n + timing * timing), 2), Number(timing, 2),
          Number(scatter, 2));
    }
  }
  return html;
}

std::string FitSection(const CalibrationReportContent& content) {
  const auto& summary = content.summary;
  std::string html = "<h2 id=\"fit-summary\">Fit summary</h2>\n<table>\n";
  html += Row({"parameter", "value", "unit",
               fmt::format("{:.0f} % interval", 100 * content.options.uncertainty.confidence_level),
               "note"},
              true);
  for (const auto& parameter : summary.parameters) {
    const std::string interval =
        parameter.confidence_interval
            ? fmt::format("[{}, {}]", Number(parameter.confidence_interval->first),
                          Number(parameter.confidence_interval->second))
            : "none (" + EscapeHtml(WithFlags(summary.uncertainty.message)) + ")";
    html += Row({EscapeHtml(parameter.name), Number(parameter.value), EscapeHtml(parameter.unit),
                 interval, parameter.at_bound ? "at the edge of its search range" : ""});
  }
  html += "</table>\n<table class=\"facts\">\n";
  const auto add = [&html](const std::string& name, const std::string& value) {
    html += Row({name, value});
  };
  add("contact law", EscapeHtml(std::string(dem::ToString(summary.law.kind))));
  add("objective", EscapeHtml(std::string(ToString(summary.objective))));
  add("residual chi&sup2;", Number(summary.residual));
  add("data points / degrees of freedom",
      fmt::format("{} / {}", summary.data_points, summary.degrees_of_freedom));
  add("reduced chi&sup2;",
      summary.degrees_of_freedom > 0 ? Number(summary.reduced_chi_square) : std::string("n/a"));
  add("AIC / BIC", Number(summary.aic) + " / " + Number(summary.bic));
  add("implied first impact e / eta",
      Number(summary.implied_restitution, 4) + " / " + Number(summary.implied_energy_loss, 4));
  add("optimiser stop", EscapeHtml(WithFlags(summary.stop_message)));
  add("drop simulations", std::to_string(summary.evaluations));
  add("uncertainty", EscapeHtml(WithFlags(summary.uncertainty.model)));
  add("model adequacy", EscapeHtml(WithFlags(summary.adequacy.message)));
  for (const auto& warning : summary.warnings) add("warning", EscapeHtml(WithFlags(warning)));
  add("time (fit / total)",
      Number(summary.fit_time_s, 3) + " s / " + Number(summary.total_time_s, 3) + " s");
  html += "</table>\n";
  return html;
}

std::string CheckSection(const CalibrationReportContent& content) {
  const auto& check = content.summary.check;
  std::string html = "<h2 id=\"analytic-check\">Analytic check</h2>\n";
  if (!check.applicable) {
    return html + "<p>Not applicable: " + EscapeHtml(WithFlags(check.message)) + ".</p>\n";
  }
  const std::string& name = check.parameter;
  html += check.parameter == "gamma_n"
              ? "<p>For the Walton&ndash;Braun law eta = 2 gamma_n / (1 + gamma_n) (Walton &amp; "
                "Braun 1986), so the measured mean energy loss gives gamma_n without any "
                "simulation.</p>\n"
              : "<p>Closed form: " + EscapeHtml(check.formula) + " (gravity-free), inverted for " +
                    EscapeHtml(name) + " without any simulation.</p>\n";
  html += "<table class=\"facts\">\n";
  html += Row({"measured eta-bar", Number(check.energy_loss_mean, 4) + " &plusmn; " +
                                       Number(check.energy_loss_mean_uncertainty, 2)});
  html += Row({EscapeHtml(name) + " from the formula", Number(check.formula_value, 5)});
  html += Row({EscapeHtml(name) + " fitted", Number(check.fitted_value, 5)});
  html += Row({"fitted &minus; formula", Number(check.difference, 4)});
  html += Row({"time-step error in " + EscapeHtml(name), Number(check.time_step_error, 4)});
  html += Row({"formula model error in " + EscapeHtml(name), Number(check.model_error, 4)});
  html += "</table>\n";
  html += fmt::format("<p class=\"{}\">{}{}</p>\n", check.warning ? "warning" : "",
                      check.warning ? "Warning: " : "", EscapeHtml(WithFlags(check.message)));
  return html;
}

}  // namespace

std::string EscapeHtml(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&#39;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

std::string CalibrationReportHtml(const CalibrationReportContent& content) {
  const auto& card = content.card;
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<title>bouncecal calibration report: " +
          EscapeHtml(std::string(dem::ToString(content.summary.law.kind))) + "</title>\n";
  html += "<style>" + std::string(kStyle) + "</style>\n</head>\n<body>\n";
  html += "<h1>Calibration report: " +
          EscapeHtml(std::string(dem::ToString(content.summary.law.kind))) + "</h1>\n";
  html += fmt::format("<p>bouncecal {} &middot; created {} UTC &middot; {} sequence(s)</p>\n",
                      EscapeHtml(card.tool_version), EscapeHtml(card.created_utc),
                      content.summary.sequences.size());
  html += InputsSection(content);
  html += RecordingsSection(content);
  html += FitSection(content);
  html += CheckSection(content);
  html += "<h2 id=\"plots\">Plots</h2>\n";
  for (const auto& [caption, svg] : content.figures) {
    html +=
        "<figure>\n" + svg + "\n<figcaption>" + EscapeHtml(caption) + "</figcaption>\n</figure>\n";
  }
  html += ImpactsSection(content);
  html +=
      "<h2 id=\"material-card\">Material card</h2>\n<p>As written by <code>bouncecal "
      "calibrate --card</code>; scenes and <code>bouncecal export</code> read it.</p>\n";
  html += "<pre>" + EscapeHtml(content.card_json) + "</pre>\n";
  html +=
      "<details><summary>Full fit result (JSON, as <code>bouncecal calibrate --json</code>)"
      "</summary>\n<pre>" +
      EscapeHtml(content.fit_json) + "</pre></details>\n";
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace bouncecal::apps
