#include "pack_run.h"

#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <system_error>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/pack_projection.h"
#include "bouncecal/dem/packing_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "option_names.h"
#include "output_target.h"
#include "pack_output_folder.h"
#include "pack_plot.h"
#include "pack_results.h"
#include "shell_quote.h"
#include "stop_signals.h"

namespace bouncecal::apps {
namespace {

// A one-line progress bar with simulated time and ETA, redrawn in place; only on a terminal.
void DrawProgress(const dem::PackProgress& p) {
  const double fraction = p.duration_s > 0 ? p.time_s / p.duration_s : 1.0;
  const int width = 30;
  const int filled = static_cast<int>(fraction * width);
  const double eta = p.remaining_wall_s;
  std::fprintf(stderr, "\r[%s%s] t = %.3f / %.3f s, %lld particles, %.0f s elapsed, ETA %.0f s ",
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), p.time_s,
               p.duration_s, static_cast<long long>(p.particles), p.wall_s, eta);
  std::fflush(stderr);
}

bool Unstable(const dem::PackSummary& s) { return s.stop_reason == dem::PackStopReason::kUnstable; }

}  // namespace

void RunPack(const PackArgs& args) {
  const TextOutputs text({{"--json", &args.json}});
  std::FILE* out = text.human();
  // From the start: a signal while the scene loads stops the run after its first step.
  const StopSignals signals;
  const dem::Scene scene = dem::LoadScene(args.scene);
  dem::PackOptions options;
  options.threads = args.threads;
  options.skin_diameters = args.skin_diameters;
  options.min_skin_diameters = args.min_skin_diameters;
  options.allow_unstable_step = args.allow_unstable_step;
  options.single_precision_contacts = args.precision == "single";
  dem::CheckDurationOverride(scene, args.duration_s);
  options.duration_s = args.duration_s;
  if (!args.resume.empty()) options.resume_checkpoint = ReadCheckpoint(args.resume);
  options.resume_name = args.resume;
  options.checkpoint_every_s = args.checkpoint_every_s;
  const bool terminal = isatty(fileno(stderr)) != 0;
  if (terminal) options.progress = DrawProgress;
  const std::filesystem::path dir =
      args.out.empty() ? scene.outputs.directory : std::filesystem::path(args.out);
  const std::filesystem::path created = FirstMissingFolder(dir);
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw OutputError(fmt::format("cannot create the output folder {} ({}); pass -o DIR",
                                  dir.string(), error.message()));
  }
  try {
    CheckOutputsWritable(dir, args.json);
  } catch (const OutputError&) {
    if (!created.empty()) std::filesystem::remove_all(created, error);
    throw;
  }
  // Only once the scene has passed every check of the set-up: a refused run leaves an earlier
  // run's outputs as they were. A resumed run continues the outputs of the run it resumes (its
  // dumps up to the checkpoint); a killed run's temporaries go either way.
  options.started = [&] {
    std::fprintf(stderr, "%s\n", dem::DescribeProjection(scene, options).c_str());
    RemoveStaleTemporaries(dir);
    if (args.resume.empty()) RemoveEarlierOutputs(dir);
  };
  const std::filesystem::path checkpoint_path = dir / kCheckpointName;
  options.checkpoint = [&](const std::string& bytes, double) {
    WriteFileAtomically(checkpoint_path, bytes);
  };
  options.stop_requested = [&signals] { return signals.requested(); };
  if (scene.outputs.snapshot_interval_s > 0) {
    options.snapshot = [&](const dem::ParticleSnapshot& snap) {
      std::ostringstream text;
      dem::WriteLammpsDump(text, snap, scene);
      WriteFileAtomically(dir / fmt::format("dump.{:09d}.lammpstrj", snap.step), text.str());
    };
  }
  dem::PackSummary summary;
  try {
    summary = dem::RunPacking(scene, options);
  } catch (const std::exception&) {
    // A scene refused while setting up (e.g. a missing or garbled start-positions file) leaves
    // nothing behind: not even the output folder this run created.
    if (!created.empty()) std::filesystem::remove_all(created, error);
    throw;
  }
  if (terminal) std::fprintf(stderr, "\n");
  for (const auto& warning : summary.warnings) {
    fmt::print(stderr, "bouncecal: warning: {}: {}\n", scene.source.string(), WithFlags(warning));
  }
  for (const auto& note : summary.notes) {
    fmt::print(stderr, "bouncecal: note: {}: {}\n", scene.source.string(), WithFlags(note));
  }
  WritePackTables(dir, scene, summary);
  WritePackSummaryJson(dir, args.json, scene, summary);
  const bool interrupted = summary.stop_reason == dem::PackStopReason::kInterrupted;
  // An unstable run has no profile to plot and may have no history row left; gnuplot failing on
  // that would turn the instability (status 3) into an output error (status 4).
  if (args.plot && !Unstable(summary) && !interrupted) PlotPacking(dir, scene);
  fmt::print(out, "{}: {} ({})\n", scene.name, WithFlags(summary.message), summary.physics);
  if (!Unstable(summary)) {
    fmt::print(out, "packing density {:.4f}, mean coordination {:.3f} ({} particles measured)\n",
               summary.packing_density, summary.coordination.mean, summary.coordination.particles);
  }
  fmt::print(out,
             "{} particles, {} steps, {:.1f} s wall on {} thread(s), {:.3g} particle-steps/s\n",
             summary.particles, summary.steps, summary.wall_s, summary.threads,
             summary.particle_steps_per_s);
  fmt::print(out, "outputs in {}\n", dir.string());
  if (Unstable(summary)) {
    throw ConfigError(fmt::format("{}: {}", scene.source.string(), summary.message));
  }
  if (summary.boiling) {
    throw ConfigError(fmt::format("{}: {}", scene.source.string(), summary.message));
  }
  if (interrupted) {
    throw InterruptedError(fmt::format(
        "{} at t = {:.6g} s; the state is saved in {}; continue with: bouncecal pack {} --resume "
        "{} (and the same --duration-s, --skin-diameters, --min-skin-diameters and --output as "
        "this run)",
        signals.signal() == SIGINT ? "interrupted (SIGINT)" : "stopped (SIGTERM)",
        summary.simulated_s, checkpoint_path.string(), SingleQuotedForShell(args.scene),
        SingleQuotedForShell(checkpoint_path.string())));
  }
}

}  // namespace bouncecal::apps
