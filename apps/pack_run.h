#ifndef BOUNCECAL_APPS_PACK_RUN_H_
#define BOUNCECAL_APPS_PACK_RUN_H_

#include <filesystem>
#include <optional>
#include <string>

#include "bouncecal/dem/packing.h"

namespace bouncecal::apps {

// What `bouncecal pack` was asked (pack_command.cc declares the options that fill it).
struct PackArgs {
  std::string scene;
  int threads = 1;
  std::filesystem::path json;
  std::string out;
  std::optional<double> duration_s;  // unset: the scene's duration_s
  double skin_diameters = bouncecal::dem::PackOptions{}.skin_diameters;
  double min_skin_diameters = bouncecal::dem::PackOptions{}.min_skin_diameters;
  bool allow_unstable_step = false;
  std::string precision = "double";  // --precision: "double" or "single" (contacts only)
  bool plot = false;
  double checkpoint_every_s = 0;  // simulated seconds; 0: no periodic checkpoint
  std::string resume;             // a checkpoint file to continue from
  std::string scene_template;     // --template: write this template instead of running
};

// Runs the scene: sets up the output folder, runs dem::RunPacking with progress, checkpoints and
// dumps, writes the results (CSV tables, summary.json, --json, --plot) and prints the summary.
// Throws ConfigError for an unstable or boiling run and InterruptedError, after saving the
// checkpoint, when a signal stopped it.
void RunPack(const PackArgs& args);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PACK_RUN_H_
