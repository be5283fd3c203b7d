#include "pack_plot.h"

#include <fmt/core.h>

#include <cstdlib>
#include <string>

#include "bouncecal/atomic_file.h"
#include "bouncecal/error.h"
#include "shell_quote.h"

namespace bouncecal::apps {
namespace {

// A gnuplot single-quoted string holds anything but a quote, which is written twice.
std::string GnuplotQuoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void PlotPacking(const std::filesystem::path& dir, const dem::Scene& scene) {
  const std::string up = scene.dimension == 3 ? "z" : "y";
  const std::string script = fmt::format(
      "set datafile separator ','\n"
      "set terminal pngcairo size 900,600 noenhanced\n"
      "set grid\n"
      "set output {0}\n"
      "set title {1}\n"
      "set xlabel 'height {2} (m)'\nset ylabel 'solid fraction'\n"
      "plot {3} using 1:2 skip 1 with lines lw 2 title 'profile'\n"
      "set output {4}\n"
      "set title {5}\n"
      "set xlabel 'time (s)'\nset ylabel 'packing density'\nset y2label 'kinetic energy (J)'\n"
      "set logscale y2\nset y2tics\n"
      "plot {6} using 1:2 skip 1 with linespoints title 'density', "
      "'' using 1:($3>0?$3:NaN) skip 1 axes x1y2 with lines title 'kinetic energy'\n",
      // Paths and the scene name are quoted: a quote in them must not end the string early.
      GnuplotQuoted((dir / "profile.png").string()),
      GnuplotQuoted(scene.name + ": solid fraction vs height"), up,
      GnuplotQuoted((dir / "profile.csv").string()), GnuplotQuoted((dir / "history.png").string()),
      GnuplotQuoted(scene.name + ": packing density and kinetic energy vs time"),
      GnuplotQuoted((dir / "history.csv").string()));
  const auto script_path = dir / "plots.gp";
  WriteFileAtomically(script_path, script);
  const std::string command = "gnuplot " + SingleQuotedForShell(script_path.string()) + " 2>&1";
  if (std::system(command.c_str()) != 0) {
    throw OutputError(fmt::format("gnuplot failed on {}; is gnuplot installed (gnuplot-nox)?",
                                  script_path.string()));
  }
}

}  // namespace bouncecal::apps
