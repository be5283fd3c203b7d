#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "bouncecal/export/drop_deck.h"
#include "bouncecal/export/packing_deck.h"
#include "bouncecal/export/scene_packing.h"
#include "commands.h"
#include "option_names.h"

namespace bouncecal::apps {
namespace {

struct ExportArguments {
  std::string material;
  std::string engine;
  std::string output_dir;
  calibrate::DropDeckOptions drop;
  std::optional<double> time_step_s;
  bool drop_height_given = false;
  std::string scene;  // empty: no packing deck
  int processes = 2;
};

// Single quotes keep any folder name intact when the user pastes the printed command.
std::string ShellQuoted(const std::string& text) {
  if (text.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./") ==
      std::string::npos) {
    return text;
  }
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

void RunExport(const ExportArguments& arguments) {
  if (arguments.output_dir == "-") {
    throw ConfigError(
        "-o -: export writes a deck of several files, which cannot go to standard output; give "
        "a folder");
  }
  calibrate::DropDeckOptions options = arguments.drop;
  options.engine = calibrate::EngineFromString(arguments.engine);
  options.time_step_s = arguments.time_step_s;
  const auto material = calibrate::ReadExportMaterial(arguments.material);
  // The card's own drop height unless the user chose one.
  if (!arguments.drop_height_given && material.drop_height_m) {
    options.drop_height_m = *material.drop_height_m;
  }
  const calibrate::Deck deck = calibrate::ExportDropDeck(material, options);

  // Everything is generated (and so validated) before the first file is written.
  std::optional<calibrate::Deck> packing;
  std::string law_note;
  if (!arguments.scene.empty()) {
    const dem::Scene scene = dem::LoadScene(arguments.scene);
    calibrate::PackingDeckOptions packing_options;
    packing_options.engine = options.engine;
    packing_options.processes = arguments.processes;
    packing_options.scene_source = arguments.scene;
    packing = calibrate::MakePackingDeck(material, calibrate::PackingDeckSpecFromScene(scene),
                                         packing_options);
    if (dem::ToJson(scene.material.law) != dem::ToJson(material.law)) {
      law_note = fmt::format(
          "  Note: the scene names the law {} but the deck uses the card's {}: exporting a card "
          "means exporting its law.\n",
          dem::ToJson(scene.material.law).dump(), dem::ToJson(material.law).dump());
    }
  }
  const std::filesystem::path folder = arguments.output_dir;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error || !std::filesystem::is_directory(folder)) {
    throw OutputError(
        fmt::format("-o {}: cannot create the deck folder ({}); choose a writable "
                    "folder",
                    folder.string(), error ? error.message() : "not a folder"));
  }
  for (const auto& file : deck.files) WriteFileAtomically(folder / file.name, file.content);
  if (packing) {
    for (const auto& file : packing->files) {
      WriteFileAtomically(folder / file.name, file.content);
    }
  }

  fmt::print(
      "bouncecal export: {} single-drop check deck for material card {} (drop from {} m{})\n",
      calibrate::ToString(options.engine), material.source, options.drop_height_m,
      arguments.drop_height_given ? ""
      : material.drop_height_m    ? ", the card's fit height"
                                  : ", default");
  for (const auto& file : deck.files) fmt::print("  wrote {}\n", (folder / file.name).string());
  fmt::print("Mapping and expected deviation:\n");
  for (const auto& note : deck.notes) fmt::print("  - {}\n", WithFlags(note));
  fmt::print(
      "Expected: restitution {:.6f} for every wall bounce, within +-{:.2f} % from the time "
      "step ({} steps of {:.4g} s, {:.4g} s simulated).\n",
      deck.expected_restitution, 100 * deck.time_step_error_bound, deck.steps, deck.time_step_s,
      deck.duration_s);
  if (material.implied_restitution &&
      std::abs(*material.implied_restitution - deck.expected_restitution) > 1e-6) {
    fmt::print(
        "  Note: the card states implied restitution {:.6f}; the deck reproduces the "
        "law's gravity-free closed form {:.6f} (the card's figure may include gravity, drag or "
        "time-step effects of the fit's simulation).\n",
        *material.implied_restitution, deck.expected_restitution);
  }
  fmt::print("Run it (writes {} there, one 'time_s z_m vz_mps' line every {:.4g} s):\n",
             (folder / deck.trajectory_file_name).string(), deck.output_interval_s);
  fmt::print("  cd {} && {}\n", ShellQuoted(folder.string()), deck.run_command);
  fmt::print("Then compare every bounce with the expectation:\n  bouncecal export-check {}\n",
             ShellQuoted(folder.string()));
  if (packing) {
    fmt::print("Packing scene {}:\n", arguments.scene);
    for (const auto& file : packing->files) {
      fmt::print("  wrote {}\n", (folder / file.name).string());
    }
    // The law is mapped again for the scene's particles, which may differ from the card's ball.
    for (const auto& note : packing->notes) fmt::print("  - {}\n", WithFlags(note));
    fmt::print("{}", law_note);
    fmt::print("Run it ({} steps of {:.4g} s):\n  cd {} && {}\n", packing->steps,
               packing->time_step_s, ShellQuoted(folder.string()), packing->run_command);
  }
}

}  // namespace

void AddExportCommand(CLI::App& app) {
  auto arguments = std::make_shared<ExportArguments>();
  auto* command = app.add_subcommand(
      "export",
      "Write a LAMMPS or LIGGGHTS input deck that checks a calibrated material: one ball dropped "
      "on a wall, its 'time z vz' written to trajectory.txt, the law mapped honestly where the "
      "engine lacks it");
  command->add_option("--material", arguments->material, "Material card (JSON) to export")
      ->required();
  command->add_option("--engine", arguments->engine, "Target engine: lammps (lmp) or liggghts")
      ->required()
      ->check(CLI::IsMember({"lammps", "liggghts"}));
  command
      ->add_option("-o,--output", arguments->output_dir,
                   "Folder for the deck (created if missing; files replaced atomically)")
      ->required();
  command
      ->add_option(
          "--drop-height-m", arguments->drop.drop_height_m,
          "Release gap between the ball's lowest point and the wall, m (> 0; default: the card's "
          "fit.drop_height_m, else 0.2)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--gravity-mps2", arguments->drop.gravity_mps2,
                   "Gravitational acceleration, m/s^2 (> 0)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--time-step-s", arguments->time_step_s,
                   "Engine time step, s (default: largest step whose restitution error bound "
                   "stays within --max-step-error)")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-step-error", arguments->drop.max_time_step_error,
                   "Bound on the relative restitution error from the time step, fraction in "
                   "(0, 0.5]")
      ->capture_default_str()
      ->check(CLI::Range(1e-9, 0.5));
  command
      ->add_option("--bounces", arguments->drop.bounces,
                   "Number of rebounds the run covers, 1..1000")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  command->add_option("--scene", arguments->scene,
                      "Packing scene file (JSON, bouncecal-scene/1): also write in.pack, the "
                      "scene with the card's law, for mpirun");
  command
      ->add_option("--processes", arguments->processes,
                   "MPI ranks in the printed packing run command, 1..4096 (1: serial)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  command->footer(
      "Example:\n"
      "  bouncecal export --material steel.json --engine lammps -o deck-lammps \\\n"
      "      --scene samples/scenes/paper000_cylinder_pour.json\n"
      "  (cd deck-lammps && lmp -in in.drop -log log.lammps)\n"
      "  bouncecal export-check deck-lammps\n"
      "  (cd deck-lammps && mpirun -np 2 lmp -in in.pack -log log.lammps)");
  auto* drop_height = command->get_option("--drop-height-m");
  command->callback([arguments, drop_height] {
    arguments->drop_height_given = drop_height->count() > 0;
    RunExport(*arguments);
  });
}

}  // namespace bouncecal::apps
