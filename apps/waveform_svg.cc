#include "waveform_svg.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "calibration_html.h"

namespace bouncecal::apps {
namespace {

// Distinct in colour and, printed in grey, in lightness.
constexpr std::array<const char*, 6> kSequenceColours = {"#1f5fa8", "#d17a00", "#2a8a3a",
                                                         "#8a2aa0", "#a02a2a", "#2a8a8a"};
constexpr const char* kRejectedColour = "#c0392b";

// A tick spacing of 1, 2 or 5 times a power of ten giving about `target` intervals.
double NiceStep(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0}) {
    if (factor * power >= raw) return factor * power;
  }
  return 10 * power;
}

// The largest 1, 2 or 5 times a power of ten that is at most `peak` (> 0): at least 0.4 of it.
double NiceTickWithin(double peak) {
  const double power = std::pow(10.0, std::floor(std::log10(peak)));
  for (double factor : {5.0, 2.0, 1.0}) {
    // The relative slack keeps a peak of exactly 0.5 (rounded from below) its own tick.
    if (factor * power <= peak * (1 + 1e-9)) return factor * power;
  }
  return power;
}

// The last time anything happens, for an axis without a known duration.
double LastEventS(const RecordingView& view) {
  double last = 0;
  for (const auto& sequence : view.sequences) {
    if (!sequence.onsets_s.empty()) last = std::max(last, sequence.onsets_s.back());
  }
  for (const auto& event : view.rejected) last = std::max(last, event.time_s);
  return last;
}

}  // namespace

std::string WaveformSvg(const RecordingView& view, const WaveformSvgLayout& layout) {
  double duration_s = view.duration_s;
  if (view.waveform && !view.waveform->time_s.empty()) {
    duration_s = std::max(duration_s, view.waveform->time_s.back());
  }
  if (!(duration_s > 0)) duration_s = std::max(1.1 * LastEventS(view), 1e-3);
  const double x0 = layout.left, x1 = layout.width - layout.right;
  const auto x_of = [&](double t_s) { return x0 + (x1 - x0) * t_s / duration_s; };
  const double centre = 0.5 * (layout.wave_top + layout.wave_bottom);
  const double half = 0.5 * (layout.wave_bottom - layout.wave_top);
  const double bracket_y = layout.wave_top - 40, marker_top = layout.wave_top - 20;
  const double marker_tip = layout.wave_top - 8, cross_y = layout.wave_bottom + 16;
  const double axis_y = layout.wave_bottom + 32;

  std::string svg = fmt::format(
      "<svg class=\"waveform-figure\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:g}\" "
      "height=\"{1:g}\" viewBox=\"0 0 {0:g} {1:g}\" role=\"img\" aria-label=\"{2}\" "
      "font-family=\"sans-serif\" font-size=\"11\">\n",
      layout.width, layout.height,
      EscapeHtml("waveform of " + view.audio.filename().string() +
                 " with its impacts and rejected events"));
  svg += fmt::format(
      "<rect class=\"plot-area\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
      "fill=\"#fafafe\" stroke=\"#ccc\" data-t0-s=\"0\" data-t1-s=\"{:.9g}\"/>\n",
      x0, bracket_y - 14, x1 - x0, cross_y + 8 - (bracket_y - 14), duration_s);

  // Time axis.
  svg += fmt::format("<g class=\"axis\" stroke=\"#444\" fill=\"#222\">\n");
  svg += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>\n", x0,
                     axis_y, x1, axis_y);
  const double step = NiceStep(duration_s, 10);
  for (int i = 0; i * step <= duration_s * (1 + 1e-9); ++i) {
    const double t = i * step, x = x_of(t);
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\"/><text x=\"{0:.1f}\" "
        "y=\"{3:.1f}\" stroke=\"none\" text-anchor=\"middle\">{4:g}</text>\n",
        x, axis_y, axis_y + 5, axis_y + 17, std::round(t / step) * step);
  }
  svg += fmt::format(
      "<text x=\"{:.1f}\" y=\"{:.1f}\" stroke=\"none\" text-anchor=\"middle\">time t (s)</text>\n",
      0.5 * (x0 + x1), axis_y + 33);
  svg += "</g>\n";

  // Waveform: one vertical stroke from min to max per pixel column.
  if (view.waveform && !view.waveform->time_s.empty()) {
    const auto& w = *view.waveform;
    double peak = 1e-6;
    for (std::size_t c = 0; c < w.min.size(); ++c)
      peak = std::max({peak, std::abs(w.min[c]), std::abs(w.max[c])});
    std::string path;
    for (std::size_t c = 0; c < w.time_s.size(); ++c) {
      double top = centre - half * w.max[c] / peak, bottom = centre - half * w.min[c] / peak;
      if (bottom - top < 1) {  // a quiet column still shows as a 1 px line
        top = 0.5 * (top + bottom) - 0.5;
        bottom = top + 1;
      }
      path += fmt::format("M{:.1f} {:.1f}V{:.1f}", x_of(w.time_s[c]), top, bottom);
    }
    svg += fmt::format(
        "<path class=\"waveform\" d=\"{}\" stroke=\"#4a5a70\" stroke-width=\"1\" fill=\"none\"/>\n",
        path);
    // Amplitude ticks at 0 and at plus and minus the largest 1-2-5 value within the peak, drawn
    // at their true heights: labels that are values of the scale, not the peak's digits at the
    // band's edges. The trace is in the recording's own units (full scale 1), high-passed.
    const double tick = NiceTickWithin(peak);
    svg += "<g class=\"amplitude-axis\" text-anchor=\"end\" fill=\"#222\" stroke=\"#444\">";
    for (const double value : {tick, 0.0, -tick}) {
      const double y = centre - half * value / peak;
      svg += fmt::format(
          "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\"/><text "
          "class=\"amplitude-tick\" data-value=\"{3:g}\" x=\"{4:.1f}\" y=\"{1:.1f}\" "
          "dominant-baseline=\"middle\" stroke=\"none\">{3:g}</text>",
          x0 - 5, y, x0, value == 0 ? 0.0 : value, x0 - 8);
    }
    svg += fmt::format(
        "<text transform=\"translate(14 {:.1f}) rotate(-90)\" text-anchor=\"middle\" "
        "stroke=\"none\">amplitude</text></g>\n",
        centre);
  }

  // Sequences: a bracket with the name, and a marker over every impact.
  for (std::size_t s = 0; s < view.sequences.size(); ++s) {
    const auto& sequence = view.sequences[s];
    if (sequence.onsets_s.empty()) continue;
    const char* colour = kSequenceColours[s % kSequenceColours.size()];
    const double first = x_of(sequence.onsets_s.front()), last = x_of(sequence.onsets_s.back());
    const std::string name =
        fmt::format("{}: {} impacts{}", sequence.label, sequence.onsets_s.size(),
                    sequence.fitted ? "" : " (too few for the fit: not used)");
    svg += fmt::format(
        "<g class=\"sequence\" stroke=\"{0}\" fill=\"{0}\"><title>{1}</title><path d=\"M{2:.1f} "
        "{3:.1f}V{4:.1f}H{5:.1f}V{3:.1f}\" fill=\"none\" stroke-width=\"1.5\"/><text "
        "x=\"{2:.1f}\" y=\"{6:.1f}\" stroke=\"none\">{1}</text></g>\n",
        colour, EscapeHtml(name), first, bracket_y + 8, bracket_y, last, bracket_y - 4);
    for (std::size_t k = 0; k < sequence.onsets_s.size(); ++k) {
      const double t = sequence.onsets_s[k], x = x_of(t);
      svg += fmt::format(
          "<g class=\"impact\" data-time-s=\"{0:.9g}\" fill=\"{1}\" stroke=\"{1}\"><title>{2}, "
          "impact {3}: onset {0:.6f} s</title><path d=\"M{4:.2f} {5:.1f}L{6:.2f} {5:.1f}L{7:.2f} "
          "{8:.1f}Z\" stroke=\"none\"/><line x1=\"{7:.2f}\" y1=\"{8:.1f}\" x2=\"{7:.2f}\" "
          "y2=\"{9:.1f}\" stroke-opacity=\"0.35\"/></g>\n",
          t, colour, EscapeHtml(sequence.label), k + 1, x - 5, marker_top, x + 5, x, marker_tip,
          layout.wave_bottom);
    }
  }

  // Rejected events: a cross under the trace; the reason is the tooltip.
  for (const auto& event : view.rejected) {
    const double x = x_of(event.time_s);
    svg += fmt::format(
        "<g class=\"rejected\" data-time-s=\"{0:.9g}\" stroke=\"{1}\"><title>rejected at {0:.6f} "
        "s: {2}</title><path d=\"M{3:.2f} {5:.1f}L{4:.2f} {6:.1f}M{3:.2f} {6:.1f}L{4:.2f} "
        "{5:.1f}\" stroke-width=\"2\"/><line x1=\"{7:.2f}\" y1=\"{8:.1f}\" x2=\"{7:.2f}\" "
        "y2=\"{5:.1f}\" stroke-opacity=\"0.3\" stroke-dasharray=\"3 3\"/></g>\n",
        event.time_s, kRejectedColour, EscapeHtml(event.reason), x - 4, x + 4, cross_y - 4,
        cross_y + 4, x, layout.wave_top);
  }
  svg += "</svg>";
  return svg;
}

}  // namespace bouncecal::apps
