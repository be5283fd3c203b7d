#include <fmt/core.h>
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/pack_projection.h"
#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/packing_json.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "option_alias.h"
#include "option_names.h"
#include "output_target.h"
#include "scene_template_option.h"
#include "stop_signals.h"

namespace bouncecal::apps {
namespace {

struct PackArgs {
  std::string scene;
  int threads = 1;
  std::filesystem::path json;
  std::string out;
  std::optional<double> duration_s;  // unset: the scene's duration_s
  double skin_diameters = bouncecal::dem::PackOptions{}.skin_diameters;
  double min_skin_diameters = bouncecal::dem::PackOptions{}.min_skin_diameters;
  bool allow_unstable_step = false;
  bool plot = false;
  double checkpoint_every_s = 0;  // simulated seconds; 0: no periodic checkpoint
  std::string resume;             // a checkpoint file to continue from
  std::string scene_template;     // --template: write this template instead of running
};

// Where periodic and interruption checkpoints go, overwritten (atomically) by each.
constexpr const char* kCheckpointName = "checkpoint.bcpack";

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

bool Finite(const dem::HistoryPoint& h) {
  return std::isfinite(h.time_s) && std::isfinite(h.packing_density) &&
         std::isfinite(h.kinetic_energy_j) && std::isfinite(h.max_speed_mps);
}

void WriteCsvs(const std::filesystem::path& dir, const dem::Scene& scene,
               const dem::PackSummary& s) {
  std::ostringstream history;
  history << "time_s,packing_density,kinetic_energy_j,max_speed_mps,particles\n";
  for (const auto& h : s.history) {
    // A run that blew up ends in inf/nan rows (its kinetic energy overflows before the engine
    // notices); the history stops at the last row that is a number throughout.
    if (!Finite(h)) break;
    history << fmt::format("{:.6g},{:.6f},{:.6g},{:.6g},{}\n", h.time_s, h.packing_density,
                           h.kinetic_energy_j, h.max_speed_mps, h.particles);
  }
  WriteFileAtomically(dir / "history.csv", history.str());
  // The state an unstable run stopped in is not a packing: RunPacking measures no profile or
  // coordination of it and its positions may be inf/nan, so none of the final-state tables is
  // written (RemoveEarlierOutputs already took away those of an earlier run).
  if (Unstable(s)) return;
  std::ostringstream profile;
  profile << "height_m,density\n";
  for (std::size_t b = 0; b < s.profile.height_m.size(); ++b) {
    profile << fmt::format("{:.6g},{:.6f}\n", s.profile.height_m[b], s.profile.density[b]);
  }
  WriteFileAtomically(dir / "profile.csv", profile.str());
  std::ostringstream coordination;
  coordination << "coordination,particles,fraction\n";
  for (std::size_t z = 0; z < s.coordination.histogram.size(); ++z) {
    const double fraction =
        s.coordination.particles > 0
            ? static_cast<double>(s.coordination.histogram[z]) / s.coordination.particles
            : 0.0;
    coordination << fmt::format("{},{},{:.6f}\n", z, s.coordination.histogram[z], fraction);
  }
  WriteFileAtomically(dir / "coordination.csv", coordination.str());
  std::ostringstream particles;
  particles << "x_m,y_m" << (scene.dimension == 3 ? ",z_m" : "")
            << ",diameter_m,species,vx_mps,vy_mps" << (scene.dimension == 3 ? ",vz_mps" : "")
            << "\n";
  const auto& f = s.final_state;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto& x = f.position_m[i];
    const auto& v = f.velocity_mps[i];
    if (scene.dimension == 3) {
      particles << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{},{:.6g},{:.6g},{:.6g}\n", x[0], x[1],
                               x[2], 2 * f.radius_m[i], f.species[i], v[0], v[1], v[2]);
    } else {
      particles << fmt::format("{:.9g},{:.9g},{:.9g},{},{:.6g},{:.6g}\n", x[0], x[1],
                               2 * f.radius_m[i], f.species[i], v[0], v[1]);
    }
  }
  WriteFileAtomically(dir / "particles.csv", particles.str());
}

// A gnuplot single-quoted string holds anything but a quote, which is written twice.
std::string GnuplotQuoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

// A POSIX shell single-quoted word: a quote inside is closed, escaped and reopened.
std::string ShellQuoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void Plot(const std::filesystem::path& dir, const dem::Scene& scene) {
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
  const std::string command = "gnuplot " + ShellQuoted(script_path.string()) + " 2>&1";
  if (std::system(command.c_str()) != 0) {
    throw OutputError(fmt::format("gnuplot failed on {}; is gnuplot installed (gnuplot-nox)?",
                                  script_path.string()));
  }
}

// The outermost folder of `dir` that does not exist yet (empty when `dir` exists).
std::filesystem::path FirstMissingFolder(const std::filesystem::path& dir) {
  std::filesystem::path missing;
  std::error_code error;
  for (auto p = std::filesystem::absolute(dir, error); !p.empty() && !error; p = p.parent_path()) {
    if (std::filesystem::exists(p, error)) break;
    missing = p;
    if (p == p.parent_path()) break;
  }
  return missing;
}

// Throws OutputError unless the temporary that the real write of `target` starts with can be
// created (it is removed again at once). Trying is the sure test: access() says yes to root in
// folders such as /proc where no file can be made.
void ProbeWritable(const std::filesystem::path& target) { AtomicFile probe(target); }

// Everything that can stop the outputs from being written is checked before the simulation, so
// a typo in --json does not cost minutes of computing for nothing.
void CheckOutputsWritable(const std::filesystem::path& dir, const std::filesystem::path& json) {
  try {
    ProbeWritable(dir / "summary.json");
  } catch (const OutputError&) {
    throw OutputError(
        fmt::format("cannot create files in the output folder {}; make it writable or pass -o DIR",
                    dir.string()));
  }
  if (json.empty() || IsStdout(json)) return;
  const std::filesystem::path& path = json;
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw OutputError(
        fmt::format("--json {}: is a folder; give the path of a file to write", json.string()));
  }
  if (!std::filesystem::is_directory(folder, error)) {
    throw OutputError(fmt::format(
        "--json {}: {} is not an existing folder; create it or choose a path in an existing "
        "folder",
        json.string(), folder.string()));
  }
  try {
    ProbeWritable(path);
  } catch (const OutputError&) {
    throw OutputError(fmt::format(
        "--json {}: cannot create a file in {}; make it writable or choose another path",
        json.string(), folder.string()));
  }
}

// The files this command writes into its output folder (WriteCsvs, summary.json, Plot and the
// dumps named dump.<step>.lammpstrj).
bool IsPackOutputName(const std::string& name) {
  for (const char* own :
       {"history.csv", "profile.csv", "coordination.csv", "particles.csv", "summary.json",
        "profile.png", "history.png", "plots.gp", kCheckpointName}) {
    if (name == own) return true;
  }
  const std::string_view prefix = "dump.";
  const std::string_view suffix = ".lammpstrj";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  const std::string step = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return step.find_first_not_of("0123456789") == std::string::npos;
}

// A rerun into the same folder would otherwise leave the dumps and plots of the earlier run
// beside the new ones (a shorter run writes fewer dumps, a run without --plot no PNGs), and they
// would be read as this run's. Only this command's own file names go; anything else stays.
void RemoveEarlierOutputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> earlier;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    std::error_code kind_error;
    if (!entry.is_directory(kind_error) && IsPackOutputName(entry.path().filename().string())) {
      earlier.push_back(entry.path());
    }
  }
  for (const auto& path : earlier) {
    std::filesystem::remove(path, error);
    if (error) {
      throw OutputError(fmt::format(
          "cannot remove {} of an earlier run ({}); remove it by hand or pass another -o DIR",
          path.string(), error.message()));
    }
  }
}

// The whole checkpoint, read before anything in the output folder changes (it may live there).
std::string ReadCheckpoint(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(
        fmt::format("--resume {}: is a folder; give the checkpoint file ({} in the "
                    "output folder of the run to continue)",
                    path, kCheckpointName));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(fmt::format(
        "--resume {}: cannot be read; give the checkpoint file ({} in the output folder of the "
        "run to continue)",
        path, kCheckpointName));
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(fmt::format("--resume {}: reading it failed", path));
  return bytes;
}

// A temporary "<own output>.tmp.<pid>" (AtomicFile's name) whose process no longer runs: left by
// a run killed while writing (SIGKILL, a second SIGINT, a crash). Those of a live process,
// another run writing into the same folder right now, are left alone.
bool IsStaleTemporary(const std::string& name) {
  const auto mark = name.rfind(".tmp.");
  if (mark == std::string::npos || !IsPackOutputName(name.substr(0, mark))) return false;
  const std::string pid_text = name.substr(mark + 5);
  if (pid_text.empty() || pid_text.size() > 9 ||
      pid_text.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  const auto pid = static_cast<pid_t>(std::stol(pid_text));
  return pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH;
}

void RemoveStaleTemporaries(const std::filesystem::path& dir) {
  std::error_code error;
  std::vector<std::filesystem::path> stale;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    std::error_code kind_error;
    if (entry.is_regular_file(kind_error) && IsStaleTemporary(entry.path().filename().string())) {
      stale.push_back(entry.path());
    }
  }
  for (const auto& path : stale) {
    std::filesystem::remove(path, error);
    if (error) {
      throw OutputError(fmt::format(
          "cannot remove {}, left by a run that was killed ({}); remove it by hand or pass "
          "another --out DIR",
          path.string(), error.message()));
    }
  }
}

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
  WriteCsvs(dir, scene, summary);
  const std::string json = dem::ToJson(scene, summary).dump(2) + "\n";
  WriteFileAtomically(dir / "summary.json", json);
  if (!args.json.empty()) WriteTextOutput(args.json, json);
  const bool interrupted = summary.stop_reason == dem::PackStopReason::kInterrupted;
  // An unstable run has no profile to plot and may have no history row left; gnuplot failing on
  // that would turn the instability (status 3) into an output error (status 4).
  if (args.plot && !Unstable(summary) && !interrupted) Plot(dir, scene);
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
        summary.simulated_s, checkpoint_path.string(), ShellQuoted(args.scene),
        ShellQuoted(checkpoint_path.string())));
  }
}

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
