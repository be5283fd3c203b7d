#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"
#include "commands.h"

namespace bouncecal::apps {
namespace {

struct PackArgs {
  std::string scene;
  int threads = 1;
  std::string json;
  std::string out;
  double duration_s = -1;
  double skin_diameters = 0.1;
  bool plot = false;
};

// A one-line progress bar with simulated time and ETA, redrawn in place; only on a terminal.
void DrawProgress(const dem::PackProgress& p) {
  const double fraction = p.duration_s > 0 ? p.time_s / p.duration_s : 1.0;
  const int width = 30;
  const int filled = static_cast<int>(fraction * width);
  const double eta = fraction > 0 ? p.wall_s * (1 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r[%s%s] t = %.3f / %.3f s, %lld particles, %.0f s elapsed, ETA %.0f s ",
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), p.time_s,
               p.duration_s, static_cast<long long>(p.particles), p.wall_s, eta);
  std::fflush(stderr);
}

nlohmann::json SummaryJson(const dem::Scene& scene, const dem::PackSummary& s) {
  nlohmann::json j;
  j["scene"] = scene.source.string();
  j["physics"] = s.physics;
  j["stop_reason"] = std::string(dem::ToString(s.stop_reason));
  j["message"] = s.message;
  j["packing_density"] = s.packing_density;
  j["packing_density_by_count"] = s.packing_density_by_count;
  j["mean_coordination"] = s.coordination.mean;
  j["coordination_histogram"] = s.coordination.histogram;
  j["coordination_particles"] = s.coordination.particles;
  j["particles"] = s.particles;
  j["particles_not_inserted"] = s.particles_not_inserted;
  j["steps"] = s.steps;
  j["time_step_s"] = s.time_step_s;
  j["simulated_s"] = s.simulated_s;
  j["kinetic_energy_j"] = s.kinetic_energy_j;
  j["neighbor_rebuilds"] = s.neighbor_rebuilds;
  j["threads"] = s.threads;
  j["wall_s"] = s.wall_s;
  j["particle_steps_per_s"] = s.particle_steps_per_s;
  if (scene.dimension == 3) {
    j["band_m"] = {scene.measurement.band_min_m, scene.measurement.band_max_m};
  } else {
    j["window_m"] = {{scene.measurement.window_min_m[0], scene.measurement.window_min_m[1]},
                     {scene.measurement.window_max_m[0], scene.measurement.window_max_m[1]}};
  }
  return j;
}

void WriteCsvs(const std::filesystem::path& dir, const dem::Scene& scene,
               const dem::PackSummary& s) {
  std::ostringstream history;
  history << "time_s,packing_density,kinetic_energy_j,max_speed_mps,particles\n";
  for (const auto& h : s.history) {
    history << fmt::format("{:.6g},{:.6f},{:.6g},{:.6g},{}\n", h.time_s, h.packing_density,
                           h.kinetic_energy_j, h.max_speed_mps, h.particles);
  }
  WriteFileAtomically(dir / "history.csv", history.str());
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

void RunPack(const PackArgs& args) {
  const dem::Scene scene = dem::LoadScene(args.scene);
  dem::PackOptions options;
  options.threads = args.threads;
  options.skin_diameters = args.skin_diameters;
  if (args.duration_s >= 0) options.duration_s = args.duration_s;
  const bool terminal = isatty(fileno(stderr)) != 0;
  if (terminal) options.progress = DrawProgress;
  const std::filesystem::path dir =
      args.out.empty() ? scene.outputs.directory : std::filesystem::path(args.out);
  const std::filesystem::path created = FirstMissingFolder(dir);
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw OutputError(fmt::format("cannot create the output folder {} ({}); pass --out DIR",
                                  dir.string(), error.message()));
  }
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
  WriteCsvs(dir, scene, summary);
  const std::string json = SummaryJson(scene, summary).dump(2) + "\n";
  WriteFileAtomically(dir / "summary.json", json);
  if (!args.json.empty()) WriteFileAtomically(args.json, json);
  if (args.plot) Plot(dir, scene);
  fmt::print("{}: {} ({})\n", scene.name, summary.message, summary.physics);
  fmt::print("packing density {:.4f}, mean coordination {:.3f} ({} particles measured)\n",
             summary.packing_density, summary.coordination.mean, summary.coordination.particles);
  fmt::print("{} particles, {} steps, {:.1f} s wall on {} thread(s), {:.3g} particle-steps/s\n",
             summary.particles, summary.steps, summary.wall_s, summary.threads,
             summary.particle_steps_per_s);
  fmt::print("outputs in {}\n", dir.string());
  if (summary.stop_reason == dem::PackStopReason::kUnstable) {
    throw ConfigError(summary.message);
  }
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
      "--json result.json --plot");
  // No ExistingFile check: a missing scene is an input-file error (status 2), not a usage one.
  command->add_option("scene", args->scene, "Scene file (JSON)")->required();
  command
      ->add_option("--threads", args->threads,
                   "Worker threads (count, >= 1); results are bit-identical for any count")
      ->check(CLI::Range(1, 1024));
  command->add_option("--json", args->json, "Also write the summary JSON to this file");
  command->add_option("--out", args->out,
                      "Output folder for CSV, dumps and plots (default: the scene's "
                      "outputs.directory)");
  command
      ->add_option("--duration", args->duration_s,
                   "Simulated time in s, overriding the scene's duration_s")
      ->check(CLI::Range(0.0, 1e6));
  command
      ->add_option("--skin", args->skin_diameters,
                   "Verlet skin in particle diameters (dimensionless, default 0.1)")
      ->check(CLI::Range(0.0, 10.0));
  command->add_flag("--plot", args->plot, "Write profile.png and history.png with gnuplot");
  command->callback([args] { RunPack(*args); });
}

}  // namespace bouncecal::apps
