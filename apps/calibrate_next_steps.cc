#include "calibrate_next_steps.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <string_view>

namespace bouncecal::apps {
namespace {

// Quoted only when the shell would change it, so that the usual names read as typed.
std::string Quoted(const std::string& text) {
  const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || std::string_view("_./=:,+-%@").find(c) != std::string::npos;
  });
  if (plain) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string StemOf(const std::filesystem::path& path) {
  const std::string stem = path.stem().string();
  return stem.empty() ? std::string("recording") : stem;
}

}  // namespace

std::string GivenArguments(const CLI::App& command, std::initializer_list<std::string> skip) {
  std::string positionals;
  std::string options;
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0) continue;
    const std::string name = option->get_name();
    if (name == "--help" || std::find(skip.begin(), skip.end(), name) != skip.end()) continue;
    if (!option->nonpositional()) {
      for (const auto& value : option->results()) positionals += " " + Quoted(value);
    } else if (option->get_type_size_max() == 0) {
      for (std::size_t i = 0; i < option->count(); ++i) options += " " + name;
    } else {
      for (const auto& value : option->results()) options += " " + name + " " + Quoted(value);
    }
  }
  return positionals + options;
}

std::string NextSteps(const CalibrationRun& run) {
  const std::string recording = Quoted(run.first_recording.string());
  std::string text = "next steps:\n";
  std::filesystem::path card = run.card;
  if (card.empty()) {
    card = StemOf(run.first_recording) + "_material.json";
    text += fmt::format("  bouncecal calibrate{}{} --card {}\n", run.arguments,
                        run.ball_given ? "" : " --ball BALL", Quoted(card.string()));
    text += run.ball_given
                ? "      the same fit, written as a material card (the law, its parameters and "
                  "the ball)\n"
                : "      the same fit, written as a material card, which needs the ball: --ball "
                  "NAME (bouncecal calibrate --help lists them) or --diameter-m with "
                  "--density-kg-per-m3\n";
  }
  const std::string quoted_card = Quoted(card.string());
  const std::string height =
      run.drop_height_m ? fmt::format("{:g}", *run.drop_height_m) : std::string("HEIGHT_M");
  text +=
      fmt::format("  bouncecal compare {} --material {} --drop-height-m {} --plot {}_compare.png\n",
                  recording, quoted_card, height, StemOf(run.first_recording));
  text += run.drop_height_m
              ? "      measured bounce heights against the card's simulated drop\n"
              : "      measured bounce heights against the card's simulated drop; compare needs "
                "the release height, which this fit did not have\n";
  text += fmt::format("  bouncecal export --material {} --engine lammps -o {}_lammps\n",
                      quoted_card, StemOf(card));
  text +=
      "      a LAMMPS deck that drops the calibrated ball (--engine liggghts for LIGGGHTS; "
      "--scene FILE adds a packing run); bouncecal export-check checks it\n";
  return text;
}

}  // namespace bouncecal::apps
