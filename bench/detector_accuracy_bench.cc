// Detector accuracy on synthetic drops with exact ground truth, condition by condition and seed
// by seed: recall, extra detections, onset errors, interval errors (what e_k and eta_k are made
// of) and the error of eta-bar over the first three impacts against what the exact onsets give.
// Onset errors are also shown less each drop's own median (abs50/abs95: a constant offset per
// recording cancels in every interval), with the share of them within two stated sigmas.
// docs/detector.md quotes its tables. It prints figures and asserts nothing.
//
//   build/bench/detector_accuracy_bench                  # every condition, 12 seeds each
//   build/bench/detector_accuracy_bench --seeds 40 --only chain
//   build/bench/detector_accuracy_bench --only table --verbose   # onsets outside 2 sigmas
//   build/bench/detector_accuracy_bench --only "=rubber on table"  # that condition alone
// The drops are retimed from their whole response as DetectImpactsInFile does: below 20 kHz
// always, above it where the drop determines its contact durations (response_timing.h);
// --response-timing-everywhere retimes every drop even without them, --first-lobe-at-pcm none
// at 20 kHz and above (before 2026-12-02); --dump PREFIX writes each drop and its truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "bouncecal/audio/bounce_analysis.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/response_timing.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/error.h"

namespace {

using bouncecal::audio::SynthesisOptions;

struct Condition {
  std::string name;
  std::function<void(SynthesisOptions&)> apply;
};

// A steel ball on a steel plate resting on a table (modes ringing tens of ms), 48 kHz, 30 dB
// referred to the weakest impact; drop height, restitution and loudness vary with the seed so
// that every seed is another experiment.
SynthesisOptions Base(int seed) {
  SynthesisOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  const double u = std::fmod(0.6180339887 * seed, 1.0);
  const double w = std::fmod(0.7548776662 * seed, 1.0);
  options.drop.drop_height_m = 0.15 + 0.35 * u;
  options.drop.restitution.constant = 0.55 + 0.35 * w;
  options.drop.min_flight_s = 0.03;
  options.peak_amplitude = 0.2 + 0.5 * std::fmod(0.5698402910 * seed, 1.0);
  for (auto& mode : options.modes) mode.decay_s *= 0.1;
  bouncecal::audio::NoiseOptions noise;
  noise.snr_db = 30;
  noise.reference = bouncecal::audio::SnrReference::kWeakestImpact;
  options.noise = noise;
  return options;
}

// A ping-pong ball on a wooden table (TableTopModes): the ball's thin shell rings too (three modes
// near 3.2 kHz dying in 3-5 ms), high restitution, air drag (terminal speed 9 m/s) and a sharp
// click.
void PingPongOnTable(SynthesisOptions& o) {
  o.modes = bouncecal::audio::TableTopModes();
  for (double f : {3100.0, 3240.0, 3390.0}) o.modes.push_back({f, 0.004, 0.6});
  o.contact_duration_s = 300e-6;
  o.drop.drop_height_m = 0.3;
  o.drop.restitution.constant = 0.88 + 0.04 * std::fmod(0.7548776662 * o.seed, 1.0);
  o.drop.terminal_speed_mps = 9.0;
  o.drop.min_flight_s = 0.04;
  o.chain = bouncecal::audio::RecordingChain{};
  o.click_gain = 0.3;
  bouncecal::audio::ReverbOptions reverb;
  reverb.rt60_s = 0.35;
  reverb.direct_to_reverberant_db = 3;
  reverb.echoes = {{0.0015, -14.0}, {0.006, -10.0}};
  o.reverb = reverb;
}

// A soft rubber ball (0.8 ms contact) on the table, whose later impacts land in the ringing of
// the earlier ones.
void RubberOnTable(SynthesisOptions& o) {
  o.modes = bouncecal::audio::TableTopModes();
  o.contact_duration_s = 800e-6;
  o.drop.drop_height_m = 0.5;
  o.drop.restitution.constant = 0.74 + 0.06 * std::fmod(0.7548776662 * o.seed, 1.0);
  o.chain = bouncecal::audio::RecordingChain{};
  o.click_gain = 0.15;
  o.amplitude_speed_exponent = 1.5;
  bouncecal::audio::ReverbOptions reverb;
  reverb.rt60_s = 0.3;
  reverb.direct_to_reverberant_db = 4;
  reverb.echoes = {{0.0015, -14.0}, {0.006, -10.0}};
  o.reverb = reverb;
}

// A 1 ms contact on the long-ringing plate (modes at a third of the free plate's decays).
void SoftContactOnPlate(SynthesisOptions& o) {
  o.modes = bouncecal::audio::SteelPlateModes();
  for (auto& mode : o.modes) mode.decay_s *= 0.3;
  o.contact_duration_s = 1e-3;
  o.drop.drop_height_m = 0.2;
  o.chain = bouncecal::audio::RecordingChain{};
  o.click_gain = 0.15;
  bouncecal::audio::ReverbOptions reverb;
  reverb.rt60_s = 0.25;
  reverb.direct_to_reverberant_db = 6;
  reverb.echoes = {{0.0015, -14.0}, {0.006, -10.0}};
  o.reverb = reverb;
}

std::vector<Condition> Conditions() {
  using namespace bouncecal::audio;
  return {
      {"clean 48k", [](SynthesisOptions&) {}},
      {"snr 15 dB", [](SynthesisOptions& o) { o.noise->snr_db = 15; }},
      {"contact 150 us", [](SynthesisOptions& o) { o.contact_duration_s = 150e-6; }},
      {"16 kHz", [](SynthesisOptions& o) { o.sample_rate_hz = 16000; }},
      {"44.1 kHz", [](SynthesisOptions& o) { o.sample_rate_hz = 44100; }},
      {"room + 9 ms echo",
       [](SynthesisOptions& o) {
         ReverbOptions reverb;
         reverb.rt60_s = 0.3;
         reverb.echoes = {{0.009, -12.0}};
         o.reverb = reverb;
       }},
      {"early reflection 2 ms",
       [](SynthesisOptions& o) {
         ReverbOptions reverb;
         reverb.rt60_s = 0.25;
         reverb.direct_to_reverberant_db = 6;
         reverb.echoes = {{0.002, -6.0}, {0.011, -9.0}};
         o.reverb = reverb;
       }},
      {"precursor 7 ms", [](SynthesisOptions& o) { o.precursor = PrecursorOptions{}; }},
      {"level jitter 3 dB", [](SynthesisOptions& o) { o.level_jitter_db = 3; }},
      {"free plate",
       [](SynthesisOptions& o) {
         o.modes = SteelPlateModes();
         o.drop.drop_height_m = 0.2;
       }},
      // The free plate at 16 kHz through a real chain: impacts in its tail are picked on the
      // prediction innovation, whose fit needs enough samples at a low rate.
      {"free plate 16k chain",
       [](SynthesisOptions& o) {
         o.modes = SteelPlateModes();
         o.drop.drop_height_m = 0.2;
         o.sample_rate_hz = 16000;
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
       }},
      {"band limit 0.45 fs 48k",
       [](SynthesisOptions& o) { o.band_limit_hz = 0.45 * o.sample_rate_hz; }},
      {"band limit 0.45 fs 16k",
       [](SynthesisOptions& o) {
         o.sample_rate_hz = 16000;
         o.band_limit_hz = 0.45 * o.sample_rate_hz;
       }},
      // A real recording chain: rendered at >= 384 kHz and decimated by a linear-phase
      // anti-aliasing filter (energy appears before contact, the more the louder the impact),
      // or its minimum-phase counterpart, with the contact's acceleration-noise click.
      {"chain linear 48k",
       [](SynthesisOptions& o) {
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
         o.contact_duration_s = 35e-6;
       }},
      {"chain linear 44.1k",
       [](SynthesisOptions& o) {
         o.sample_rate_hz = 44100;
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
         o.contact_duration_s = 35e-6;
       }},
      {"chain linear 16k",
       [](SynthesisOptions& o) {
         o.sample_rate_hz = 16000;
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
       }},
      {"chain minimum 48k",
       [](SynthesisOptions& o) {
         o.chain = RecordingChain{};
         o.chain->phase = AdcFilterPhase::kMinimum;
         o.click_gain = 0.2;
       }},
      {"chain linear 16k jitter",
       [](SynthesisOptions& o) {
         o.sample_rate_hz = 16000;
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
         o.level_jitter_db = 3;
       }},
      // A soft ball (rubber, 0.8 ms contact) through a real chain: its plate response keeps
      // growing for milliseconds after a weak first lobe.
      {"soft ball 0.8 ms chain",
       [](SynthesisOptions& o) {
         o.chain = RecordingChain{};
         o.click_gain = 0.15;
         o.contact_duration_s = 800e-6;
         o.level_jitter_db = 3;
       }},
      {"ping-pong on table", PingPongOnTable},
      {"ping-pong on table 16k",
       [](SynthesisOptions& o) {
         PingPongOnTable(o);
         o.sample_rate_hz = 16000;
       }},
      {"ping-pong on table 40 dB re first",
       [](SynthesisOptions& o) {
         PingPongOnTable(o);
         o.noise->snr_db = 40;
         o.noise->reference = SnrReference::kFirstImpact;
         o.drop.min_flight_s = 0.02;
       }},
      {"rubber on table", RubberOnTable},
      {"rubber on table 16k",
       [](SynthesisOptions& o) {
         RubberOnTable(o);
         o.sample_rate_hz = 16000;
       }},
      {"soft 1 ms on plate", SoftContactOnPlate},
      {"soft 1 ms on plate 16k",
       [](SynthesisOptions& o) {
         SoftContactOnPlate(o);
         o.sample_rate_hz = 16000;
       }},
      {"plate chain 8k",
       [](SynthesisOptions& o) {
         o.sample_rate_hz = 8000;
         o.chain = RecordingChain{};
         o.click_gain = 0.2;
       }},
      {"low e 0.3",
       [](SynthesisOptions& o) {
         o.drop.restitution.constant = 0.3;
         o.drop.drop_height_m = 0.5;
       }},
  };
}

struct Tally {
  int drops = 0;
  int drops_with_sequence = 0;
  int truth = 0;
  int found = 0;
  int extra = 0;
  std::vector<double> errors_s;  // signed, matched impacts
  // Signed, less the median of their own drop (the recording's constant offset, which cancels
  // in every interval), and whether each lies within two of its stated sigmas.
  std::vector<double> centred_errors_s;
  int within_two_sigma = 0;
  std::vector<double> interval_errors_s;  // |error| of intervals between consecutive matches
  // Those intervals within two sigmas of their two onsets' stated uncertainties in quadrature:
  // what the calibration's intervals use (only relative times enter them).
  int intervals_within_two_sigma = 0;
  std::vector<double> eta_errors;  // |eta-bar(1-3) detected - exact|, per drop
};

constexpr double kMatchS = 1e-3;

// Mean of 1 - e_k^2 over the first three ratios e_k = dt_k / dt_{k-1} (no drop height): five
// onsets.
double EtaBar(const std::vector<double>& onsets) {
  double sum = 0;
  for (int k = 1; k <= 3; ++k) {
    const double e = (onsets[k + 1] - onsets[k]) / (onsets[k] - onsets[k - 1]);
    sum += 1 - e * e;
  }
  return sum / 3;
}

// Command-line switches beyond the conditions.
struct Flags {
  // Retime from the whole response at every rate, not only below 20 kHz (what
  // DetectImpactsInFile does): measures what the stage would do to 44.1-96 kHz WAVs.
  bool response_timing_everywhere = false;
  bool first_lobe_at_pcm = false;
  bool verbose = false;  // print every onset outside 2 stated sigmas
  std::string dump;      // write each drop as DUMP<seed>.wav and .csv (truth)
};

void Score(const SynthesisOptions& options, const Flags& flags, Tally& tally) {
  auto recording = bouncecal::audio::SynthesizeBounces(options);
  if (!flags.dump.empty()) {
    const std::string base = flags.dump + std::to_string(options.seed);
    bouncecal::audio::WriteRecordingOptions w;
    w.encoding = bouncecal::audio::SampleEncoding::kFloat;
    bouncecal::audio::WriteRecording(base + ".wav", recording.channels, w);
    FILE* f = std::fopen((base + ".csv").c_str(), "w");
    std::fputs(bouncecal::audio::TruthCsv(recording).c_str(), f);
    std::fclose(f);
  }
  auto detection = bouncecal::audio::DetectImpacts(recording.channels[0]);
  // As DetectImpactsInFile does (response_timing.h): retimed from the response, at 20 kHz and
  // above only where the drop determines its contact durations.
  bouncecal::audio::RecordingInfo info;
  info.sample_rate_hz = options.sample_rate_hz;
  auto timing = bouncecal::audio::ResponseTimingFor(info);
  if (flags.response_timing_everywhere) timing.require_contact_durations = false;
  if (!flags.first_lobe_at_pcm || !timing.require_contact_durations) {
    bouncecal::audio::RetimeFromResponses(detection, recording.channels[0].samples, 0, timing);
  }
  const auto grouping = bouncecal::audio::GroupBounces(detection);
  const auto& impacts = detection.impacts;
  const auto truth = recording.BallImpactOnsetsS();
  ++tally.drops;
  tally.drops_with_sequence += grouping.sequences.empty() ? 0 : 1;
  tally.truth += static_cast<int>(truth.size());
  std::vector<int> match(truth.size(), -1);
  std::vector<bool> used(impacts.size(), false);
  for (std::size_t t = 0; t < truth.size(); ++t) {
    int best = -1;
    for (std::size_t i = 0; i < impacts.size(); ++i) {
      const double error = std::fabs(impacts[i].onset_s - truth[t]);
      if (!used[i] && error < kMatchS &&
          (best < 0 ||
           error < std::fabs(impacts[static_cast<std::size_t>(best)].onset_s - truth[t]))) {
        best = static_cast<int>(i);
      }
    }
    if (best >= 0) {
      match[t] = best;
      used[static_cast<std::size_t>(best)] = true;
      ++tally.found;
      tally.errors_s.push_back(impacts[static_cast<std::size_t>(best)].onset_s - truth[t]);
    }
  }
  for (std::size_t i = 0; i < impacts.size(); ++i) tally.extra += used[i] ? 0 : 1;
  std::vector<double> drop_errors;
  for (std::size_t t = 0; t < truth.size(); ++t) {
    if (match[t] >= 0) {
      drop_errors.push_back(impacts[static_cast<std::size_t>(match[t])].onset_s - truth[t]);
    }
  }
  if (!drop_errors.empty()) {
    auto sorted = drop_errors;
    std::sort(sorted.begin(), sorted.end());
    const double offset = sorted[sorted.size() / 2];
    for (std::size_t t = 0; t < truth.size(); ++t) {
      if (match[t] < 0) continue;
      const auto& impact = impacts[static_cast<std::size_t>(match[t])];
      const double centred = impact.onset_s - truth[t] - offset;
      tally.centred_errors_s.push_back(centred);
      tally.within_two_sigma += std::fabs(centred) <= 2 * impact.onset_uncertainty_s ? 1 : 0;
      if (flags.verbose && std::fabs(centred) > 2 * impact.onset_uncertainty_s)
        std::printf(
            "  seed %llu impact %zu t %.4f err %+.1f us sigma %.1f us peak %.1f dB rise %.1f resid "
            "%d\n",
            (unsigned long long)options.seed, t, truth[t], centred * 1e6,
            impact.onset_uncertainty_s * 1e6, impact.peak_dbfs, impact.rise_db,
            impact.residual_only);
    }
  }
  for (std::size_t t = 1; t < truth.size(); ++t) {
    if (match[t] < 0 || match[t - 1] < 0) continue;
    const double detected = impacts[static_cast<std::size_t>(match[t])].onset_s -
                            impacts[static_cast<std::size_t>(match[t - 1])].onset_s;
    tally.interval_errors_s.push_back(std::fabs(detected - (truth[t] - truth[t - 1])));
    const double sigma =
        std::hypot(impacts[static_cast<std::size_t>(match[t])].onset_uncertainty_s,
                   impacts[static_cast<std::size_t>(match[t - 1])].onset_uncertainty_s);
    tally.intervals_within_two_sigma += tally.interval_errors_s.back() <= 2 * sigma ? 1 : 0;
  }
  if (truth.size() >= 5 && !grouping.sequences.empty()) {
    std::vector<double> detected;
    for (int t = 0; t < 5; ++t) {
      if (match[static_cast<std::size_t>(t)] >= 0) {
        detected.push_back(
            impacts[static_cast<std::size_t>(match[static_cast<std::size_t>(t)])].onset_s);
      }
    }
    if (detected.size() == 5) {
      tally.eta_errors.push_back(std::fabs(EtaBar(detected) - EtaBar(truth)));
    }
  }
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()))];
}

std::vector<double> Abs(std::vector<double> values) {
  for (double& v : values) v = std::fabs(v);
  return values;
}

// The 95th percentile of the eta-bar errors, or "-" where no drop had its first five impacts
// found (eta-bar over ratios 1-3 needs them; a drop of e = 0.3 has only three).
std::string EtaCell(const std::vector<double>& eta_errors) {
  if (eta_errors.empty()) return "-";
  char cell[32];
  std::snprintf(cell, sizeof cell, "%.4f", Quantile(eta_errors, 0.95));
  return cell;
}

// One row per condition (--only picks them), over the given seeds.
void PrintTable(int seeds, const Flags& flags, const std::string& only) {
  std::printf("%-24s %5s %9s %5s %8s %8s %8s %8s %8s %8s %6s %6s\n", "condition", "seq", "found",
              "extra", "bias_us", "abs50_us", "abs95_us", "int50_us", "int95_us", "deta95",
              "in2sig", "int2sig");
  for (const auto& condition : Conditions()) {
    if (!only.empty() && (only[0] == '=' ? condition.name != only.substr(1)
                                         : condition.name.find(only) == std::string::npos)) {
      continue;
    }
    Tally tally;
    for (int seed = 1; seed <= seeds; ++seed) {
      auto options = Base(seed);
      condition.apply(options);
      Score(options, flags, tally);
    }
    const double bias = Quantile(tally.errors_s, 0.5);
    const auto& centred = tally.centred_errors_s;
    std::printf("%-24s %2d/%-2d %4d/%-4d %5d %8.1f %8.1f %8.1f %8.1f %8.1f %8s %5.0f%% %5.0f%%\n",
                condition.name.c_str(), tally.drops_with_sequence, tally.drops, tally.found,
                tally.truth, tally.extra, bias * 1e6, Quantile(Abs(centred), 0.5) * 1e6,
                Quantile(Abs(centred), 0.95) * 1e6, Quantile(tally.interval_errors_s, 0.5) * 1e6,
                Quantile(tally.interval_errors_s, 0.95) * 1e6, EtaCell(tally.eta_errors).c_str(),
                100.0 * tally.within_two_sigma / std::max<std::size_t>(1, centred.size()),
                100.0 * tally.intervals_within_two_sigma /
                    std::max<std::size_t>(1, tally.interval_errors_s.size()));
  }
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 12;
  Flags flags;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc) {
      flags.dump = argv[++i];
    } else if (!std::strcmp(argv[i], "--verbose")) {
      flags.verbose = true;
    } else if (!std::strcmp(argv[i], "--response-timing-everywhere")) {
      flags.response_timing_everywhere = true;
    } else if (!std::strcmp(argv[i], "--first-lobe-at-pcm")) {
      flags.first_lobe_at_pcm = true;
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: %s [--seeds N] [--only SUBSTRING] [--verbose] [--dump PREFIX] "
                   "[--response-timing-everywhere] [--first-lobe-at-pcm]\n",
                   argv[0]);
      return 2;
    }
  }
  try {
    PrintTable(seeds, flags, only);
  } catch (const bouncecal::Error& error) {
    // A --dump folder that does not exist, or a full disk: one line, not an uncaught exception.
    std::fprintf(stderr, "detector_accuracy_bench: %s\n", error.what());
    return 1;
  }
  return 0;
}
