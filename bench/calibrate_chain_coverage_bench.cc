// Whole-chain coverage of calibrate's 95 % interval and the level and power of its speed-trend
// test: drops whose restitution scatters from impact to impact are rendered as sound by the
// project's synthesiser (audio::SynthesizeBounces: plate modes, room reverb, 35 dB noise), written
// as 48 kHz PCM16 WAV, detected and grouped as `bouncecal calibrate` does (LoadSequences), and
// fitted with calibrate's defaults (walton-braun, eta-bar of the first 3 impacts), with and
// without the drop height, one recording or several fitted jointly.
//
//   calibrate_chain_coverage_bench [--seeds N (200)] [--threads T (2)] [--power-seeds M (N)]
//                                  [--skip-coverage] [--skip-power] [--material copper|anvil|glass]
//                                  [--jitters 0,1,3,5] [--recordings 1,3,5]
//                                  [--between-percent B (0)]
//
// --material, --jitters (percent) and --recordings select rows of the coverage table (by default
// copper and anvil, every jitter and count), so a change that concerns some rows can be measured
// on them with many seeds; only the selected materials' and jitters' recordings are synthesised.
// --between-percent makes the recordings of one seed differ: each recording's e is the material's
// times (1 + B z_r), z_r standard normal per recording (a ball dropped on another day or another
// spot of the plate), and the truth is then the gamma_n of the population's mean energy loss,
// 1 - e^2 (1 + j^2) (1 + B^2); its rows of one recording cannot cover it and are not meaningful.
//
// Each recording is synthesised and detected once and reused by every row that needs it (the
// 1-, 3- and 5-recording rows of a seed share their first recordings; both height options share
// all). The material's gamma_n is what the same fit returns for a drop without scatter or timing
// noise whose restitution sqrt(1 - eta_m) has the material's mean energy loss
// eta_m = 1 - e^2 (1 + j^2) (what averages over ever more impacts converge to, the fit's own
// time-step bias and the DEM drop's contact against the synthesiser's included). The trend test is
// a false alarm on every one of these constant-e fits; its power is measured on drops whose e
// really changes with impact speed (Thornton's elastic-plastic law, viscoelastic Hertz, a power
// law), fitted with the constant walton-braun.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/calibrate/fit.h"
#include "bouncecal/calibrate/sequence_input.h"
#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/random_stream.h"
#include "bouncecal/worker_pool.h"

namespace {

namespace audio = bouncecal::audio;
namespace calibrate = bouncecal::calibrate;
namespace dem = bouncecal::dem;

constexpr double kGravity = 9.81;
constexpr int kMaxRecordings = 5;
constexpr double kShortestFlightS = 0.004;  // the ball then chatters and rolls

struct Material {
  const char* name;
  double restitution;
  double drop_height_m;
};
// A steel ball on copper (the paper's eta-bar = 0.58 region) and on a steel anvil, the table of
// docs/calibration.md; on glass (a lively ball, ~40 impacts a drop) only with --material glass.
const Material kMaterials[] = {{"steel on copper", 0.65, 0.20},
                               {"steel on anvil", 0.80, 0.35},
                               {"steel on glass", 0.92, 0.30}};
const double kJitters[] = {0.0, 0.01, 0.03, 0.05};

// e(v) of the drop before the per-impact scatter.
using RestitutionOfSpeed = std::function<double(double speed_mps)>;

// The synthesiser's contact duration at an impact speed (its Hertz pulse, SynthesisOptions).
double ContactDurationS(const audio::SynthesisOptions& synthesis, double speed_mps) {
  return synthesis.contact_duration_s * std::pow(speed_mps / synthesis.reference_speed_mps,
                                                 synthesis.contact_duration_speed_exponent);
}

// The impacts of a drop whose e_k = law(v_k) (1 + jitter z_k): ballistic flights (no drag), and
// each onset interval holds the contact that starts it and the flight after it, as a real drop's
// do (and the independent generator's of ../shared/coverage-suite); contact-free intervals would
// differ from any DEM drop's by a pattern that grows as the flights shorten.
std::vector<audio::ImpactSpec> DropImpacts(const audio::SynthesisOptions& synthesis,
                                           const RestitutionOfSpeed& law, double drop_height_m,
                                           double jitter, bouncecal::RandomStream& draws) {
  std::vector<audio::ImpactSpec> impacts;
  double onset = 0.3 + std::sqrt(2 * drop_height_m / kGravity);
  double speed = std::sqrt(2 * kGravity * drop_height_m);
  for (int k = 0; k < 60; ++k) {
    impacts.push_back({onset, speed, 0});
    const double contact = ContactDurationS(synthesis, speed);
    const double e = std::min(law(speed) * (1 + jitter * draws.Gaussian()), 0.999);
    speed *= e;
    const double flight = 2 * speed / kGravity;
    if (flight < kShortestFlightS) break;
    onset += contact + flight;
  }
  return impacts;
}

// A drop rendered (plate modes, reverb, 35 dB noise) and detected.
std::optional<calibrate::MeasuredSequence> RecordDrop(const RestitutionOfSpeed& law,
                                                      double drop_height_m, double jitter,
                                                      std::uint64_t seed, std::uint64_t recording,
                                                      const std::string& tag) {
  bouncecal::RandomStream draws(seed, recording, 7);
  audio::SynthesisOptions synthesis;
  synthesis.impacts = DropImpacts(synthesis, law, drop_height_m, jitter, draws);
  synthesis.reverb = audio::ReverbOptions{};
  synthesis.noise = audio::NoiseOptions{};
  synthesis.seed = seed * 16 + recording;
  const auto rendered = audio::SynthesizeBounces(synthesis);
  const auto path = std::filesystem::temp_directory_path() /
                    ("bouncecal_chain_" + tag + "_" + std::to_string(seed) + "_" +
                     std::to_string(recording) + ".wav");
  audio::WriteRecording(path, rendered.channels);
  std::optional<calibrate::MeasuredSequence> sequence;
  try {
    auto sequences = calibrate::LoadSequences({path});
    sequence = sequences.front();
  } catch (const std::exception&) {
  }
  std::filesystem::remove(path);
  return sequence;
}

calibrate::FitOptions Options(bool known_height, double drop_height_m) {
  calibrate::FitOptions options;
  options.analytic_check = false;
  options.uncertainty.threads = 1;
  if (known_height) {
    options.drop.drop_height_m = drop_height_m;
    options.drop_height_given = true;
  }
  return options;
}

// What the same fit returns for the drop's exact onsets (no scatter, no timing noise, the same
// contacts in the intervals) with the material's mean energy loss.
double MaterialGamma(const Material& material, double jitter, double between, bool known_height) {
  const double e = std::sqrt(material.restitution * material.restitution * (1 + jitter * jitter) *
                             (1 + between * between));
  bouncecal::RandomStream draws(0, 0, 0);  // drawn, but times a jitter of 0
  calibrate::MeasuredSequence exact;
  exact.source = "exact";
  for (const auto& impact : DropImpacts(
           audio::SynthesisOptions{}, [e](double) { return e; }, material.drop_height_m, 0, draws))
    exact.impacts.push_back({impact.onset_s, 0.0});
  return calibrate::Fit({exact}, Options(known_height, material.drop_height_m)).parameters[0].value;
}

struct Outcome {
  bool fitted = false;
  bool covered = false;
  bool trend = false;
  double width = 0;
};

Outcome FitAndScore(const std::vector<calibrate::MeasuredSequence>& sequences,
                    const calibrate::FitOptions& options, double truth) {
  Outcome outcome;
  try {
    const auto summary = calibrate::Fit(sequences, options);
    const auto& interval = summary.parameters[0].confidence_interval;
    outcome.fitted = true;
    outcome.trend = summary.adequacy.trend;
    if (interval) {
      outcome.covered = interval->first <= truth && truth <= interval->second;
      outcome.width = interval->second - interval->first;
    }
  } catch (const std::exception&) {
  }
  return outcome;
}

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// The coverage rows to run: material indices, jitter indices into kJitters, recording counts.
struct RowSelection {
  std::vector<int> materials{0, 1};
  std::vector<int> jitters{0, 1, 2, 3};
  std::vector<int> counts{1, 3, 5};
  double between = 0;  // relative sd of e between recordings
};

bool Contains(const std::vector<int>& values, int value) {
  return std::find(values.begin(), values.end(), value) != values.end();
}

void Coverage(int seeds, const RowSelection& rows, bouncecal::WorkerPool& pool) {
  const int materials = static_cast<int>(std::size(kMaterials));
  const int jitters = static_cast<int>(std::size(kJitters));
  // recordings[((m * jitters + j) * seeds + s) * kMaxRecordings + r]
  std::vector<std::optional<calibrate::MeasuredSequence>> recordings(
      static_cast<size_t>(materials * jitters * seeds * kMaxRecordings));
  double cpu = CpuSeconds();
  pool.ParallelForEach(static_cast<std::int64_t>(recordings.size()), [&](std::int64_t item) {
    const auto r = static_cast<std::uint64_t>(item % kMaxRecordings);
    const auto s = static_cast<std::uint64_t>((item / kMaxRecordings) % seeds);
    const int j = static_cast<int>((item / kMaxRecordings / seeds) % jitters);
    const int m = static_cast<int>(item / kMaxRecordings / seeds / jitters);
    if (!Contains(rows.materials, m) || !Contains(rows.jitters, j)) return;
    const auto& material = kMaterials[m];
    bouncecal::RandomStream recording_draw(5000 + s, r, 11);
    const double e = material.restitution * (1 + rows.between * recording_draw.Gaussian());
    recordings[static_cast<size_t>(item)] =
        RecordDrop([e](double) { return e; }, material.drop_height_m, kJitters[j], 5000 + s, r,
                   "coverage_" + std::to_string(m) + "_" + std::to_string(j));
  });
  const auto synthesised =
      rows.materials.size() * rows.jitters.size() * static_cast<size_t>(seeds * kMaxRecordings);
  std::printf("# %zu recordings synthesised and detected, %.2f CPU s each\n", synthesised,
              (CpuSeconds() - cpu) / static_cast<double>(synthesised));
  std::printf(
      "| material | jitter of e | drop height | recordings | material gamma_n | coverage "
      "(95 %% binomial range) | mean width | trend claimed | no fit | CPU s per fit |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  std::fflush(stdout);
  int total_trend = 0, total_tested = 0;
  for (int m : rows.materials) {
    for (int j : rows.jitters) {
      for (bool known_height : {false, true}) {
        const auto& material = kMaterials[m];
        const double truth = MaterialGamma(material, kJitters[j], rows.between, known_height);
        const auto options = Options(known_height, material.drop_height_m);
        for (int count : rows.counts) {
          std::vector<Outcome> outcomes(static_cast<size_t>(seeds));
          cpu = CpuSeconds();
          pool.ParallelForEach(seeds, [&](std::int64_t s) {
            std::vector<calibrate::MeasuredSequence> sequences;
            for (int r = 0; r < count; ++r) {
              const auto& recording = recordings[static_cast<size_t>(
                  ((m * jitters + j) * seeds + s) * kMaxRecordings + r)];
              if (!recording) return;
              sequences.push_back(*recording);
            }
            outcomes[static_cast<size_t>(s)] = FitAndScore(sequences, options, truth);
          });
          const double cpu_per_fit = (CpuSeconds() - cpu) / seeds;
          int fitted = 0, covered = 0, trend = 0;
          double width = 0;
          for (const auto& outcome : outcomes) {
            if (!outcome.fitted) continue;
            ++fitted;
            covered += outcome.covered ? 1 : 0;
            trend += outcome.trend ? 1 : 0;
            width += outcome.width;
          }
          total_trend += trend;
          total_tested += fitted;
          const double spread = 1.96 * std::sqrt(0.95 * 0.05 / std::max(fitted, 1));
          std::printf(
              "| %s | %.0f %% | %s | %d | %.4f | %.1f %% (%d of %d; %.1f-%.1f) | %.3g | %d | %d | "
              "%.3f |\n",
              material.name, 100 * kJitters[j],
              known_height ? (std::to_string(material.drop_height_m).substr(0, 4) + " m").c_str()
                           : "not given",
              count, truth, 100.0 * covered / std::max(fitted, 1), covered, fitted,
              100 * (0.95 - spread), 100 * (0.95 + spread), width / std::max(fitted, 1), trend,
              seeds - fitted, cpu_per_fit);
          std::fflush(stdout);
        }
      }
    }
  }
  std::printf("# speed-trend claims on these constant-e fits: %d of %d (%.2f %%)\n", total_trend,
              total_tested, 100.0 * total_trend / std::max(total_tested, 1));
}

// The restitution of `law` (one damping parameter) at an impact speed, for a 10 mm steel ball on
// a rigid plate.
double ClosedForm(dem::ContactLawKind kind, const std::string& name, double value, double speed) {
  dem::ContactLawConfig config{kind, {{name, value}}};
  const auto law = dem::MakeContactLaw(config);
  const calibrate::FitOptions defaults;
  const auto& ball = defaults.drop.ball;
  return dem::ClosedFormRestitutionOf(law, ball.MassKg(), ball.RadiusM(), speed).value_or(0.5);
}

// The parameter in [low, high] at which e_of(parameter) first falls to `target` going up from
// low (the first crossing on a log grid of 200, refined by bisection): an approximate closed
// form may turn back towards e = 1 beyond its validity (the Ramirez series of
// hertz-viscoelastic does, see fit.cc).
template <typename EOf>
double Solve(const EOf& e_of, double low, double high, double target) {
  double a = low;
  for (int k = 1; k <= 200; ++k) {
    double b = low * std::pow(high / low, k / 200.0);
    if (e_of(b) <= target) {
      for (int i = 0; i < 100; ++i) {
        const double middle = std::sqrt(a * b);
        (e_of(middle) > target ? a : b) = middle;
      }
      return std::sqrt(a * b);
    }
    a = b;
  }
  return high;
}

void Power(int seeds, bouncecal::WorkerPool& pool) {
  const double h0 = 0.20, v1 = std::sqrt(2 * kGravity * h0);
  const double target = 0.65;  // e of the first impact, as the copper material
  struct Law {
    std::string name;
    RestitutionOfSpeed e;
  };
  std::vector<Law> laws;
  laws.push_back(Law{"constant e = 0.65 (false alarms)", [target](double) { return target; }});
  {
    // e falls as the yield pressure does, so solve in its inverse.
    const auto e_of = [](double inverse_yield) {
      return ClosedForm(dem::ContactLawKindFromString("thornton"), "yield_pressure_pa",
                        1 / inverse_yield, 1.98);
    };
    const double yield = 1 / Solve(e_of, 1 / 5e10, 1 / 1e6, target);
    laws.push_back(
        Law{"thornton, yield pressure " + std::to_string(yield / 1e9).substr(0, 5) + " GPa",
            [yield](double v) {
              return ClosedForm(dem::ContactLawKindFromString("thornton"), "yield_pressure_pa",
                                yield, v);
            }});
  }
  {
    const auto e_of = [](double time) {
      return ClosedForm(dem::ContactLawKind::kHertzViscoelastic, "dissipative_time_s", time, 1.98);
    };
    const double time = Solve(e_of, 1e-9, 1e-3, target);
    laws.push_back(Law{
        "hertz-viscoelastic, dissipative time " + std::to_string(time * 1e6).substr(0, 5) + " us",
        [time](double v) {
          return ClosedForm(dem::ContactLawKind::kHertzViscoelastic, "dissipative_time_s", time, v);
        }});
  }
  laws.push_back(Law{"power law e = 0.65 (v / 1.98 m/s)^-0.05", [v1, target](double v) {
                       return std::min(target * std::pow(v / v1, -0.05), 0.99);
                     }});
  std::printf(
      "\n| e(v) of the drop | e at 1.98 / 0.5 / 0.1 m/s | jitter of e | trend claimed "
      "(99 %% test) | tested | CPU s per case |\n| --- | --- | --- | --- | --- | --- |\n");
  for (const auto& law : laws) {
    for (double jitter : {0.0, 0.01, 0.03}) {
      std::vector<int> claimed(static_cast<size_t>(seeds), -1);
      const double cpu = CpuSeconds();
      pool.ParallelForEach(seeds, [&](std::int64_t s) {
        const auto recording =
            RecordDrop(law.e, h0, jitter, 9000 + static_cast<std::uint64_t>(s), 0, "power");
        if (!recording) return;
        try {
          claimed[static_cast<size_t>(s)] =
              calibrate::Fit({*recording}, Options(true, h0)).adequacy.trend ? 1 : 0;
        } catch (const std::exception&) {
        }
      });
      int tested = 0, trends = 0;
      for (int c : claimed) {
        tested += c >= 0 ? 1 : 0;
        trends += c > 0 ? 1 : 0;
      }
      std::printf("| %s | %.3f / %.3f / %.3f | %.0f %% | %.1f %% (%d) | %d | %.3f |\n",
                  law.name.c_str(), law.e(1.98), law.e(0.5), law.e(0.1), 100 * jitter,
                  100.0 * trends / std::max(tested, 1), trends, tested,
                  (CpuSeconds() - cpu) / seeds);
      std::fflush(stdout);
    }
  }
}

// "1,3,5" -> {1, 3, 5}; empty when some entry is not a number.
std::vector<int> ParseList(const std::string& text) {
  std::vector<int> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    const std::string entry = text.substr(start, end - start);
    char* rest = nullptr;
    const long value = std::strtol(entry.c_str(), &rest, 10);
    if (entry.empty() || *rest != '\0') return {};
    values.push_back(static_cast<int>(value));
    start = end + 1;
  }
  return values;
}

// Indices of the percents in kJitters; empty when one is not there.
std::vector<int> JitterIndices(const std::vector<int>& percents) {
  std::vector<int> indices;
  for (int percent : percents) {
    int found = -1;
    for (size_t j = 0; j < std::size(kJitters); ++j)
      if (std::lround(100 * kJitters[j]) == percent) found = static_cast<int>(j);
    if (found < 0) return {};
    indices.push_back(found);
  }
  return indices;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 200, threads = 2, power_seeds = -1;
  bool coverage = true, power = true;
  RowSelection rows;
  bool rows_ok = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto next = [&]() { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
    if (arg == "--seeds") {
      seeds = next();
    } else if (arg == "--threads") {
      threads = next();
    } else if (arg == "--power-seeds") {
      power_seeds = next();
    } else if (arg == "--skip-coverage") {
      coverage = false;
    } else if (arg == "--skip-power") {
      power = false;
    } else if (arg == "--material" && i + 1 < argc) {
      const std::string name = argv[++i];
      rows.materials = name == "copper"  ? std::vector<int>{0}
                       : name == "anvil" ? std::vector<int>{1}
                       : name == "glass" ? std::vector<int>{2}
                                         : std::vector<int>{};
      rows_ok = rows_ok && !rows.materials.empty();
    } else if (arg == "--jitters" && i + 1 < argc) {
      rows.jitters = JitterIndices(ParseList(argv[++i]));
      rows_ok = rows_ok && !rows.jitters.empty();
    } else if (arg == "--between-percent" && i + 1 < argc) {
      char* rest = nullptr;
      const char* text = argv[++i];
      rows.between = std::strtod(text, &rest) / 100;
      rows_ok = rows_ok && rest != text && *rest == '\0' && rows.between >= 0 && rows.between < 0.2;
    } else if (arg == "--recordings" && i + 1 < argc) {
      rows.counts = ParseList(argv[++i]);
      rows_ok = rows_ok && !rows.counts.empty() &&
                std::all_of(rows.counts.begin(), rows.counts.end(),
                            [](int count) { return count >= 1 && count <= kMaxRecordings; });
    } else {
      std::fprintf(
          stderr,
          "calibrate_chain_coverage_bench: unknown argument '%s'; use --seeds N, "
          "--threads T, --power-seeds M, --skip-coverage, --skip-power, --material "
          "copper|anvil|glass, --jitters 0,1,3,5, --recordings 1,3,5, --between-percent B\n",
          arg.c_str());
      return 2;
    }
  }
  if (!rows_ok) {
    std::fprintf(
        stderr,
        "calibrate_chain_coverage_bench: --material is copper, anvil or glass, --jitters a "
        "comma list of 0, 1, 3, 5, --recordings of 1 to %d and --between-percent in [0, 20)\n",
        kMaxRecordings);
    return 2;
  }
  if (seeds < 1 || threads < 1) {
    std::fprintf(stderr, "calibrate_chain_coverage_bench: --seeds and --threads must be >= 1\n");
    return 2;
  }
  if (power_seeds < 1) power_seeds = seeds;
  std::printf(
      "# whole chain: drop with scattered e (each interval a Hertz contact and a ballistic flight) "
      "-> SynthesizeBounces (steel plate modes, "
      "reverb RT60 0.3 s, 35 dB SNR) -> 48 kHz PCM16 WAV -> LoadSequences -> calibrate::Fit "
      "(walton-braun, eta-bar of the first 3); %d seeds per row, %d threads; recordings' e differ "
      "by %.2f %%\n",
      seeds, threads, 100 * rows.between);
  bouncecal::WorkerPool pool(threads);
  if (coverage) Coverage(seeds, rows, pool);
  if (power) Power(power_seeds, pool);
  return 0;
}
