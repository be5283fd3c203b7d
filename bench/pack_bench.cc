// Timed packing run: the paper 000 pour (or any 3D scene) from one start file, reported as
// particle-steps per second. When LAMMPS (lmp, lmp_serial or lmp_stable) or LIGGGHTS (liggghts)
// is on the PATH it runs the same start positions: LAMMPS with pair gran/hooke/history, LIGGGHTS
// with pair gran model hooke/stiffness tangential history (the paper's damping mapped to a linear
// dashpot of equal restitution, docs/physics.md section 4; the same coefficients in both). Each
// runs on 1 rank, and with mpirun on --lammps-ranks ranks (default 2: the cores the target is
// stated for) twice, once with the engine's default processor grid and once with the box split
// only across gravity (`processors N 1 1`: the default grid splits the tallest side, z, so the
// settled pack lands on one rank). It prints the speed ratio against each and against the
// fastest of each engine, from this one run. Figures only: nothing here asserts a time.
//
//   pack_bench [SCENE.json] [--duration S] [--threads N] [--settle S] [--skin D] [--min-skin D]
//   [--poll-stop] [--no-lammps] [--no-liggghts]
//   [--lammps-ranks N] [--work DIR] [--precision double|single]
//
// --precision single times bouncecal with single-precision contacts (PackOptions::
// single_precision_contacts); the start and the settling stay double, so both precisions are
// timed from the same state.
// --settle S first runs the start for S seconds (untimed) and times both engines from that
// state instead: a settled pack has ~5 contacts per sphere, the costly regime of a pour.
// --poll-stop asks for a stop every step as `bouncecal pack` does (a flag that stays unset), to
// time what the poll costs.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/dem/packing.h"
#include "bouncecal/dem/scene.h"
#include "bouncecal/error.h"

namespace {

namespace dem = bouncecal::dem;

double CpuSeconds(int who = RUSAGE_SELF) {
  rusage usage{};
  getrusage(who, &usage);
  return usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6 + usage.ru_stime.tv_sec +
         usage.ru_stime.tv_usec * 1e-6;
}

bool OnPath(const std::string& name) {
  return std::system(("command -v " + name + " >/dev/null 2>&1").c_str()) == 0;
}

std::string FindLammps() {
  for (const char* name : {"lmp", "lmp_serial", "lmp_stable", "lmp_mpi"}) {
    if (OnPath(name)) return name;
  }
  return "";
}

// Walton-braun gamma_n has no LAMMPS form, so the normal damping is the linear dashpot with the
// same restitution for a particle pair (m_eff = m/2), per unit mass as gran/hooke/history and
// LIGGGHTS's hooke/stiffness take it.
double LinearDashpotGammaPerMass(const dem::Scene& scene) {
  const double k = scene.material.law.Get("stiffness_n_per_m");
  const double gamma = scene.material.law.kind == dem::ContactLawKind::kWaltonBraun
                           ? scene.material.law.Get("gamma_n")
                           : 0.5;
  const double e = std::sqrt((1 - gamma) / (1 + gamma));
  const double d = scene.particles.diameter.MaxDiameterM();
  const double m = scene.particles.species[0].density_kg_per_m3 * M_PI / 6 * d * d * d;
  const double m_eff = m / 2;
  const double c = 2 * std::sqrt(m_eff * k) * (-std::log(e)) /
                   std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
  return c / m_eff;
}

// The same scene in LAMMPS with LinearDashpotGammaPerMass's damping.
// `processors` is LAMMPS's processor-grid command ("" keeps its default grid).
std::string LammpsInput(const dem::Scene& scene, const std::filesystem::path& data,
                        std::int64_t steps, const std::string& processors) {
  const double k = scene.material.law.Get("stiffness_n_per_m");
  const double d = scene.particles.diameter.MaxDiameterM();
  const double gamma_n = LinearDashpotGammaPerMass(scene);
  // Walls: LAMMPS uses m_eff = m there, so the same damping ratio needs gamma_n / sqrt(2).
  const auto& ct = scene.container;
  std::ostringstream in;
  in << "units si\natom_style sphere\nboundary f f f\ncomm_modify vel yes\n";
  if (!processors.empty()) in << "processors " << processors << "\n";
  in << "read_data " << data.string() << "\n"
     << "pair_style gran/hooke/history " << k << " " << scene.material.tangential_stiffness_n_per_m
     << " " << gamma_n << " 0 " << scene.material.friction << " 1\npair_coeff * *\n"
     << "neighbor " << 0.1 * d << " bin\nneigh_modify delay 0\n"
     << "fix floor all wall/gran hooke/history " << k << " "
     << scene.material.tangential_stiffness_n_per_m << " " << gamma_n / std::sqrt(2.0) << " 0 "
     << scene.material.wall_friction << " 1 zplane " << ct.center_m[2] << " NULL\n"
     << "fix side all wall/gran hooke/history " << k << " "
     << scene.material.tangential_stiffness_n_per_m << " " << gamma_n / std::sqrt(2.0) << " 0 "
     << scene.material.wall_friction << " 1 zcylinder " << ct.radius_m << "\n"
     << "fix grav all gravity " << scene.gravity_mps2 << " vector 0 0 -1\n"
     << "fix integrate all nve/sphere\ntimestep " << scene.time_step_s << "\nthermo 10000\n"
     << "run " << steps << "\n";
  return in.str();
}

// The same scene in LIGGGHTS (atom_style granular reads the same Atoms lines): type 1 the
// particles, type 2 the walls, so that wall contacts keep their own damping. hooke/stiffness
// without absolute_damping is LAMMPS's gran/hooke/history (F = kn xi + m_eff gamman dxi/dt, a
// Cundall-Strack spring kt capped by friction, no tangential damping), so the coefficients are
// LammpsInput's. Its data file declares the wall type (LiggghtsData).
std::string LiggghtsInput(const dem::Scene& scene, const std::filesystem::path& data,
                          std::int64_t steps, const std::string& processors) {
  const double k = scene.material.law.Get("stiffness_n_per_m");
  const double d = scene.particles.diameter.MaxDiameterM();
  const double gamma_n = LinearDashpotGammaPerMass(scene);
  const double kt = scene.material.tangential_stiffness_n_per_m;
  const auto& ct = scene.container;
  auto per_type_pair = [](double particle, double wall) {
    std::ostringstream values;
    values << particle << " " << wall << " " << wall << " " << wall;
    return values.str();
  };
  std::ostringstream in;
  in << "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n"
     << "communicate single vel yes\nunits si\n";
  if (!processors.empty()) in << "processors " << processors << "\n";
  in << "read_data " << data.string() << "\n"
     << "neighbor " << 0.1 * d << " bin\nneigh_modify delay 0\n"
     << "fix m1 all property/global kn peratomtypepair 2 " << per_type_pair(k, k) << "\n"
     << "fix m2 all property/global kt peratomtypepair 2 " << per_type_pair(kt, kt) << "\n"
     << "fix m3 all property/global gamman peratomtypepair 2 "
     << per_type_pair(gamma_n, gamma_n / std::sqrt(2.0)) << "\n"
     << "fix m4 all property/global gammat peratomtypepair 2 0 0 0 0\n"
     << "fix m5 all property/global coefficientFriction peratomtypepair 2 "
     << per_type_pair(scene.material.friction, scene.material.wall_friction) << "\n"
     << "pair_style gran model hooke/stiffness tangential history\npair_coeff * *\n"
     << "fix floor all wall/gran model hooke/stiffness tangential history primitive type 2 "
     << "zplane " << ct.center_m[2] << "\n"
     << "fix side all wall/gran model hooke/stiffness tangential history primitive type 2 "
     << "zcylinder " << ct.radius_m << " " << ct.center_m[0] << " " << ct.center_m[1] << "\n"
     << "fix grav all gravity " << scene.gravity_mps2 << " vector 0 0 -1\n"
     << "fix integrate all nve/sphere\ntimestep " << scene.time_step_s << "\nthermo 10000\n"
     << "run " << steps << "\n";
  return in.str();
}

// The LAMMPS data file with a second atom type declared (LIGGGHTS' walls are type 2).
std::string LiggghtsData(const std::string& lammps_data) {
  std::string text = lammps_data;
  const std::string types = "\n1 atom types\n";
  const auto at = text.find(types);
  if (at != std::string::npos) text.replace(at, types.size(), "\n2 atom types\n");
  return text;
}

// FNV-1a over the bytes of the final positions and velocities: equal digests mean bit-identical
// trajectories (thread counts, engine changes that must not alter the arithmetic).
std::uint64_t StateDigest(const dem::ParticleSnapshot& snap) {
  std::uint64_t hash = 14695981039346656037ull;
  auto add = [&](const auto& vectors) {
    for (const auto& v : vectors) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(v.data());
      for (std::size_t b = 0; b < sizeof(double) * v.size(); ++b) {
        hash = (hash ^ bytes[b]) * 1099511628211ull;
      }
    }
  };
  add(snap.position_m);
  add(snap.velocity_mps);
  return hash;
}

}  // namespace

int main(int argc, char** argv) {
  // Line by line: a bench stopped during the reference engines' runs keeps bouncecal's figures.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::filesystem::path scene_path =
      std::filesystem::path(BOUNCECAL_SOURCE_DIR) / "samples/scenes/paper000_cylinder_pour.json";
  double duration = -1;
  int threads = 2;
  double settle_s = 0;
  double skin_diameters = dem::PackOptions{}.skin_diameters;
  double min_skin_diameters = dem::PackOptions{}.min_skin_diameters;
  double skin_rebuild_steps = dem::PackOptions{}.skin_rebuild_steps;
  double checkpoint_every_s = 0;
  bool run_lammps = true;
  bool run_liggghts = true;
  bool poll_stop = false;
  bool single_precision = false;  // only the timed run: both precisions time from the same start
  int lammps_ranks = 2;
  std::filesystem::path work = std::filesystem::temp_directory_path() / "bouncecal_pack_bench";
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--duration" && a + 1 < argc) {
      duration = std::atof(argv[++a]);
    } else if (arg == "--threads" && a + 1 < argc) {
      threads = std::atoi(argv[++a]);
    } else if (arg == "--settle" && a + 1 < argc) {
      settle_s = std::atof(argv[++a]);
    } else if (arg == "--skin" && a + 1 < argc) {
      skin_diameters = std::atof(argv[++a]);
    } else if (arg == "--min-skin" && a + 1 < argc) {
      min_skin_diameters = std::atof(argv[++a]);
    } else if (arg == "--skin-steps" && a + 1 < argc) {
      skin_rebuild_steps = std::atof(argv[++a]);
    } else if (arg == "--checkpoint-every" && a + 1 < argc) {
      checkpoint_every_s = std::atof(argv[++a]);
    } else if (arg == "--precision" && a + 1 < argc) {
      single_precision = std::string(argv[++a]) == "single";
    } else if (arg == "--poll-stop") {
      poll_stop = true;
    } else if (arg == "--no-lammps") {
      run_lammps = false;
    } else if (arg == "--no-liggghts") {
      run_liggghts = false;
    } else if (arg == "--lammps-ranks" && a + 1 < argc) {
      lammps_ranks = std::atoi(argv[++a]);
    } else if (arg == "--work" && a + 1 < argc) {
      work = argv[++a];
    } else {
      scene_path = arg;
    }
  }
  try {
    dem::Scene scene = dem::LoadScene(scene_path);
    if (duration >= 0) scene.duration_s = duration;
    std::filesystem::create_directories(work);
    // One start file for both engines: every particle placed at t = 0 (a pour region is made
    // tall enough to hold them all), written as a LAMMPS data file and read back.
    dem::Scene start = scene;
    start.duration_s = 0;
    if (start.insertion.kind == dem::InsertionKind::kPour) {
      start.insertion.kind = dem::InsertionKind::kRandom;
      auto& region = start.insertion.region;
      const double volume =
          scene.particles.count * scene.particles.diameter.MeanVolumeM3(scene.dimension) / 0.25;
      const double area =
          region.kind == dem::RegionKind::kCylinder
              ? M_PI * region.radius_m * region.radius_m
              : (region.max_m[0] - region.min_m[0]) * (region.max_m[1] - region.min_m[1]);
      if (region.kind == dem::RegionKind::kCylinder) {
        region.z_max_m = std::max(region.z_max_m, region.z_min_m + volume / area);
      } else {
        region.max_m[2] = std::max(region.max_m[2], region.min_m[2] + volume / area);
      }
    }
    auto placed = dem::RunPacking(start);
    const auto data = work / "start.data";
    std::ostringstream text;
    dem::WriteLammpsData(text, placed.final_state, scene);
    std::string start_data = text.str();
    bouncecal::WriteFileAtomically(data, start_data);
    if (settle_s > 0) {
      // The settled state starts at rest: the data file carries positions only.
      dem::Scene settle = scene;
      settle.insertion.kind = dem::InsertionKind::kFile;
      settle.insertion.file = data;
      settle.duration_s = settle_s;
      dem::PackOptions settle_options;
      settle_options.threads = threads;
      placed = dem::RunPacking(settle, settle_options);
      std::ostringstream settled;
      dem::WriteLammpsData(settled, placed.final_state, scene);
      start_data = settled.str();
      bouncecal::WriteFileAtomically(data, start_data);
      std::printf("start: settled for %.3g s (%s)\n", settle_s, placed.message.c_str());
    }
    scene.insertion.kind = dem::InsertionKind::kFile;
    scene.insertion.file = data;

    dem::PackOptions options;
    options.threads = threads;
    options.skin_diameters = skin_diameters;
    options.min_skin_diameters = min_skin_diameters;
    options.skin_rebuild_steps = skin_rebuild_steps;
    options.single_precision_contacts = single_precision;
    // What bouncecal pack's StopSignals::requested() reads: a flag a signal handler would set.
    static volatile std::sig_atomic_t stop_flag = 0;
    if (poll_stop) options.stop_requested = [] { return stop_flag != 0; };
    // Checkpoints as `pack --checkpoint-every-s` takes them, each written to the work folder
    // the same way (atomically): their count, size and time show what they cost a run.
    int checkpoints = 0;
    std::size_t checkpoint_bytes = 0;
    double checkpoint_write_s = 0;
    if (checkpoint_every_s > 0) {
      options.checkpoint_every_s = checkpoint_every_s;
      options.checkpoint = [&](const std::string& bytes, double) {
        const auto begin = std::chrono::steady_clock::now();
        bouncecal::WriteFileAtomically(work / "checkpoint.bcpack", bytes);
        checkpoint_write_s +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
        ++checkpoints;
        checkpoint_bytes = bytes.size();
      };
    }
    const double cpu0 = CpuSeconds();
    const auto summary = dem::RunPacking(scene, options);
    const double cpu = CpuSeconds() - cpu0;
    const double particle_steps = static_cast<double>(summary.particles) * summary.steps;
    std::printf("bouncecal: %s, %lld particles, %lld steps (%.3g s simulated), %d thread(s)\n",
                scene.name.c_str(), static_cast<long long>(summary.particles),
                static_cast<long long>(summary.steps), summary.simulated_s, threads);
    std::printf("  wall %.2f s, cpu %.2f s, %.3g particle-steps/s (wall), %.3g per cpu-second\n",
                summary.wall_s, cpu, summary.particle_steps_per_s, particle_steps / cpu);
    std::printf("  packing density %.4f, mean coordination %.3f, %lld neighbour rebuilds\n",
                summary.packing_density, summary.coordination.mean,
                static_cast<long long>(summary.neighbor_rebuilds));
    std::printf("  final state digest %016llx\n",
                static_cast<unsigned long long>(StateDigest(summary.final_state)));
    {
      rusage usage{};
      getrusage(RUSAGE_SELF, &usage);
      // ru_maxrss is in KiB on Linux: the peak of the whole bench process (start, settle, run).
      std::printf(
          "  peak resident memory %.1f MiB (%.0f bytes per particle)\n",
          static_cast<double>(usage.ru_maxrss) / 1024,
          static_cast<double>(usage.ru_maxrss) * 1024 / static_cast<double>(summary.particles));
    }
    if (checkpoints > 0) {
      std::printf("  %d checkpoints of %zu bytes (%.0f per particle), %.3f s writing them\n",
                  checkpoints, checkpoint_bytes,
                  static_cast<double>(checkpoint_bytes) / static_cast<double>(summary.particles),
                  checkpoint_write_s);
    }

    struct ReferenceRun {
      std::string engine;  // "LAMMPS" or "LIGGGHTS"
      std::string executable;
      std::string label;
      int ranks;
      std::string processors;
    };
    std::vector<ReferenceRun> runs;
    auto add_runs = [&](const std::string& engine, const std::string& executable) {
      runs.push_back({engine, executable, "1 rank", 1, ""});
      if (lammps_ranks > 1 && OnPath("mpirun")) {
        const std::string n = std::to_string(lammps_ranks);
        runs.push_back({engine, executable, n + " ranks, default grid", lammps_ranks, ""});
        runs.push_back(
            {engine, executable, n + " ranks, processors " + n + " 1 1", lammps_ranks, n + " 1 1"});
      } else if (lammps_ranks > 1) {
        std::printf("%s on %d ranks: mpirun is not installed - 1 rank only\n", engine.c_str(),
                    lammps_ranks);
      }
    };
    if (run_lammps) {
      const std::string lammps = FindLammps();
      if (lammps.empty()) {
        std::printf("LAMMPS: not installed (apt-get install lammps) - no ratio this run\n");
      } else {
        add_runs("LAMMPS", lammps);
      }
    }
    if (run_liggghts) {
      if (!OnPath("liggghts")) {
        std::printf("LIGGGHTS: not installed (apt-get install liggghts) - no ratio this run\n");
      } else {
        const auto liggghts_data = work / "start_liggghts.data";
        bouncecal::WriteFileAtomically(liggghts_data, LiggghtsData(start_data));
        add_runs("LIGGGHTS", "liggghts");
      }
    }
    struct Fastest {
      double wall = 0;
      std::string label;
    };
    Fastest fastest_lammps;
    Fastest fastest_liggghts;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const auto& run = runs[r];
      const bool liggghts = run.engine == "LIGGGHTS";
      const std::string tag = liggghts ? "liggghts" : "lammps";
      const auto input = work / ("in" + std::to_string(r) + "." + tag);
      const auto log = work / ("log" + std::to_string(r) + "." + tag);
      bouncecal::WriteFileAtomically(
          input, liggghts ? LiggghtsInput(scene, work / "start_liggghts.data", summary.steps,
                                          run.processors)
                          : LammpsInput(scene, data, summary.steps, run.processors));
      std::string command = run.executable + " -in " + input.string() + " -log " + log.string();
      if (run.ranks > 1) {
        // Open MPI refuses root unless told; CI runs as root.
        command = std::string("mpirun ") + (geteuid() == 0 ? "--allow-run-as-root " : "") + "-np " +
                  std::to_string(run.ranks) + " " + command;
      }
      command += " > /dev/null 2>&1";
      const double child_cpu0 = CpuSeconds(RUSAGE_CHILDREN);
      const auto t0 = std::chrono::steady_clock::now();
      const int status = std::system(command.c_str());
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double child_cpu = CpuSeconds(RUSAGE_CHILDREN) - child_cpu0;
      if (status != 0) {
        std::printf("%s (%s): failed (status %d); see %s\n", run.engine.c_str(), run.label.c_str(),
                    status, log.string().c_str());
        continue;
      }
      std::printf(
          "%s (%s, %s, %s): wall %.2f s, cpu %.2f s, %.3g particle-steps/s (wall); "
          "bouncecal / %s: %.2f (wall), %.2f (cpu)\n",
          run.engine.c_str(), run.executable.c_str(),
          liggghts ? "hooke/stiffness tangential history" : "gran/hooke/history", run.label.c_str(),
          wall, child_cpu, particle_steps / wall, run.engine.c_str(), wall / summary.wall_s,
          child_cpu / cpu);
      Fastest& best = liggghts ? fastest_liggghts : fastest_lammps;
      if (best.label.empty() || wall < best.wall) best = {wall, run.label};
    }
    // On a shared machine the wall ratio is noisy (run the bench on an idle one); the cpu ratios
    // above compare the work done.
    for (const auto& [engine, best] :
         {std::pair{"LAMMPS", fastest_lammps}, std::pair{"LIGGGHTS", fastest_liggghts}}) {
      if (best.label.empty()) continue;
      std::printf("speed ratio bouncecal (%d thread(s)) / fastest %s (%s): %.2f (wall)\n", threads,
                  engine, best.label.c_str(), best.wall / summary.wall_s);
    }
  } catch (const bouncecal::Error& error) {
    std::fprintf(stderr, "pack_bench: %s\n", error.what());
    return 1;
  }
  return 0;
}
