// `bouncecal pack`: its options, and what it does with them (RunPack, pack_run.cc). The run's
// parts have a file each: the output folder and checkpoints (pack_output_folder.cc), the result
// tables and summary JSON (pack_results.cc), the plots (pack_plot.cc).
#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "bouncecal/error.h"
#include "commands.h"
#include "option_alias.h"
#include "pack_output_folder.h"
#include "pack_run.h"
#include "scene_template_option.h"

namespace bouncecal::apps {
namespace {

// CLI::Range only compares, and every comparison with NaN is false: "nan" would pass it. Text
// that is no number at all is left to CLI::Range, which names it.
CLI::Validator FiniteSeconds() {
  return CLI::Validator(
      [](std::string& text) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end != text.c_str() && *end == '\0' && !std::isfinite(value)) {
          return fmt::format("{} is not a number of seconds; give a finite value in [0, 1e6]",
                             text);
        }
        return std::string();
      },
      "");
}

}  // namespace

void AddPackCommand(CLI::App& app) {
  auto args = std::make_shared<PackArgs>();
  auto* command = app.add_subcommand(
      "pack",
      "Run a multi-particle packing scene (JSON scene file, see docs/scenes.md) and measure its "
      "packing density, density profile, coordination and kinetic energy.");
  command->footer(
      "Example: bouncecal pack samples/scenes/paper000_cylinder_pour.json --threads 2 "
      "--json result.json --plot\n"
      "summary.json and --json carry \"format\": \"bouncecal-pack/1\" (docs/json.md).");
  // No ExistingFile check: a missing scene is an input-file error (status 2), not a usage one.
  auto* scene = command->add_option("scene", args->scene, "Scene file (JSON)");
  AddSceneTemplateOption(*command, args->scene_template)->excludes(scene);
  command
      ->add_option("--threads", args->threads,
                   "Worker threads (count, >= 1); results are bit-identical for any count")
      ->check(CLI::Range(1, 1024));
  command->add_option("--json", args->json,
                      "Also write the summary JSON to this file, - for stdout");
  auto* output = command->add_option("-o,--output", args->out,
                                     "Output folder for CSV, dumps and plots (default: the "
                                     "scene's outputs.directory)");
  AddDeprecatedAlias(*command, output, "--out", args->out);
  auto* duration = command
                       ->add_option("--duration-s", args->duration_s,
                                    "Simulated time in s, overriding the scene's duration_s; 0 "
                                    "measures the start state, anything else must be at least "
                                    "the scene's time_step_s")
                       ->check(FiniteSeconds())
                       ->check(CLI::Range(0.0, 1e6));
  AddDeprecatedAlias(*command, duration, "--duration", args->duration_s)
      ->check(FiniteSeconds())
      ->check(CLI::Range(0.0, 1e6));
  auto* skin = command
                   ->add_option("--skin-diameters", args->skin_diameters,
                                "Widest Verlet skin in particle diameters (default 0.1)")
                   ->check(CLI::Range(0.0, 10.0));
  AddDeprecatedAlias(*command, skin, "--skin", args->skin_diameters)->check(CLI::Range(0.0, 10.0));
  auto* min_skin = command
                       ->add_option("--min-skin-diameters", args->min_skin_diameters,
                                    "Narrowest Verlet skin in particle diameters (default 0.01): "
                                    "the skin adapts to the fastest particle at each rebuild; a "
                                    "value >= --skin-diameters fixes it")
                       ->check(CLI::Range(0.0, 10.0));
  AddDeprecatedAlias(*command, min_skin, "--min-skin", args->min_skin_diameters)
      ->check(CLI::Range(0.0, 10.0));
  command->add_flag("--allow-unstable-step", args->allow_unstable_step,
                    "Run even when time_step_s exceeds the stability limit of the scene's "
                    "stiffest contact (refused otherwise)");
  command
      ->add_option(
          "--precision", args->precision,
          "Arithmetic of the particle-particle contacts: double (default, the reference) or "
          "single (each contact force carries float rounding; about 5 % faster, see "
          "docs/packing.md)")
      ->check(CLI::IsMember({"double", "single"}));
  command->add_flag("--plot", args->plot, "Write profile.png and history.png with gnuplot");
  command
      ->add_option("--checkpoint-every-s", args->checkpoint_every_s,
                   "Write a checkpoint (" + std::string(kCheckpointName) +
                       " in the output folder) every this many SIMULATED seconds, at the next "
                       "block boundary (every 2000 steps at most), so results do not depend on "
                       "it; 0 (default): only when interrupted")
      ->check(FiniteSeconds())
      ->check(CLI::Range(0.0, 1e6));
  command->add_option("--resume", args->resume,
                      "Continue the run saved in this checkpoint file (same scene and options); "
                      "the result is bit-identical to an uninterrupted run");
  command->callback([args] {
    if (!args->scene_template.empty()) return WriteSceneTemplate(args->scene_template);
    if (args->scene.empty()) {
      throw ConfigError(
          "pack needs a SCENE file (JSON); bouncecal pack --template 3d-cylinder > "
          "scene.json writes a commented one to start from");
    }
    RunPack(*args);
  });
}

}  // namespace bouncecal::apps
