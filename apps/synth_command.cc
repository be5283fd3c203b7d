// bouncecal synth: renders a synthetic bounce recording with exact ground truth.
#include <fmt/core.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/atomic_file.h"
#include "bouncecal/audio/impact_csv.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"
#include "bouncecal/error.h"
#include "commands.h"
#include "output_target.h"

namespace bouncecal::apps {
namespace {

// Command-line values; the defaults are SynthesisOptions' own, so `synth` and the library agree.
struct SynthArguments {
  std::string output;
  std::string truth;
  std::string impact_times;
  audio::SynthesisOptions options;
  std::string surface = "plate";
  std::optional<double> snr_db;
  std::string noise_color = "white";
  std::string snr_reference = "first";
  double snr_window_s = audio::NoiseOptions{}.window_s;
  std::optional<double> reverb_rt60_s;
  double reverb_drr_db = audio::ReverbOptions{}.direct_to_reverberant_db;
  std::vector<double> echo_delay_s;
  std::vector<double> echo_gain_db;
  std::optional<double> precursor_lead_s;
  double precursor_gain_db = audio::PrecursorOptions{}.gain_db;
  std::optional<double> hum_hz;
  double hum_dbfs = audio::HumOptions{}.fundamental_dbfs;
  int hum_harmonics = audio::HumOptions{}.harmonics_count;
  std::optional<double> clip_level;
  std::optional<double> limiter_gain_db;
  audio::LimiterOptions limiter;
  std::vector<double> knock_s;
  std::vector<double> thump_s;
  std::vector<double> stray_s;
  double event_amplitude = 0.2;
  int channels = 1;
  double channel_delay_s = 0.0;
  double channel_gain_db = 0.0;
  double channel_snr_offset_db = 0.0;
  std::string format = "pcm16";
  std::string adc;  // empty: no recording chain
  audio::RecordingChain chain;
};

audio::SynthesisOptions BuildOptions(const SynthArguments& args) {
  audio::SynthesisOptions options = args.options;
  if (!args.impact_times.empty()) options.impacts = audio::ReadImpactCsv(args.impact_times);
  options.modes = args.surface == "counter" ? audio::CounterTopModes() : audio::SteelPlateModes();
  if (args.snr_db) {
    options.noise = audio::NoiseOptions{
        .snr_db = *args.snr_db,
        .color = args.noise_color == "pink" ? audio::NoiseColor::kPink : audio::NoiseColor::kWhite,
        .reference = args.snr_reference == "weakest" ? audio::SnrReference::kWeakestImpact
                                                     : audio::SnrReference::kFirstImpact,
        .window_s = args.snr_window_s};
  }
  if (args.echo_delay_s.size() != args.echo_gain_db.size()) {
    throw ConfigError(fmt::format(
        "--echo-delay-s is given {} times but --echo-gain-db {} times; give one gain per echo",
        args.echo_delay_s.size(), args.echo_gain_db.size()));
  }
  if (args.reverb_rt60_s || !args.echo_delay_s.empty()) {
    audio::ReverbOptions reverb;
    reverb.rt60_s = args.reverb_rt60_s.value_or(0.0);
    reverb.direct_to_reverberant_db = args.reverb_drr_db;
    for (size_t i = 0; i < args.echo_delay_s.size(); ++i) {
      reverb.echoes.push_back({args.echo_delay_s[i], args.echo_gain_db[i]});
    }
    options.reverb = reverb;
  }
  if (args.precursor_lead_s) {
    options.precursor = audio::PrecursorOptions{*args.precursor_lead_s, args.precursor_gain_db};
  }
  if (args.hum_hz) {
    options.hum = audio::HumOptions{*args.hum_hz, args.hum_dbfs, args.hum_harmonics};
  }
  options.clip_level = args.clip_level;
  if (args.limiter_gain_db) {
    options.limiter = args.limiter;
    options.limiter->gain_db = *args.limiter_gain_db;
  }
  if (!args.adc.empty()) {
    options.chain = args.chain;
    options.chain->phase = args.adc == "minimum-phase" ? audio::AdcFilterPhase::kMinimum
                                                       : audio::AdcFilterPhase::kLinear;
  }
  const std::pair<const std::vector<double>*, audio::SoundEventKind> extras[] = {
      {&args.knock_s, audio::SoundEventKind::kKnock},
      {&args.thump_s, audio::SoundEventKind::kThump},
      {&args.stray_s, audio::SoundEventKind::kStray}};
  for (const auto& [times, kind] : extras) {
    for (double onset_s : *times)
      options.extra_events.push_back({kind, onset_s, args.event_amplitude});
  }
  if (args.channels < 1 || args.channels > 64) {
    throw ConfigError(
        fmt::format("--channels {} is outside [1, 64]; give 1 to 64 channels", args.channels));
  }
  options.channels.clear();
  for (int c = 0; c < args.channels; ++c) {
    options.channels.push_back(
        {c * args.channel_delay_s, c * args.channel_gain_db, c * args.channel_snr_offset_db});
  }
  return options;
}

void RunSynth(const SynthArguments& args) {
  const std::filesystem::path truth_path = args.truth;
  const TextOutputs text({{"--truth", &truth_path}});
  std::FILE* out = text.human();
  // libsndfile writes what the name asks for only for these; any other name (x.mp3, -) would get
  // WAV bytes under a name that promises something else.
  CheckOutputExtension("-o/--output", args.output, {".wav", ".flac"},
                       "synth writes WAV or FLAC, chosen by the extension");
  const audio::SynthesisOptions options = BuildOptions(args);
  const audio::SynthesizedRecording recording = audio::SynthesizeBounces(options);
  const audio::WriteRecordingOptions write_options{
      .container = audio::ContainerForPath(args.output),
      .encoding = audio::SampleEncodingFromString(args.format)};
  // Check the truth path before writing audio, so a bad --truth leaves no orphaned WAV either.
  std::optional<AtomicFile> truth;
  if (!args.truth.empty() && !IsStdout(truth_path)) truth.emplace(args.truth);
  const audio::WriteRecordingSummary summary =
      audio::WriteRecording(args.output, recording.channels, write_options);
  if (truth) {
    truth->stream() << audio::TruthCsv(recording);
    truth->Commit();
  } else if (IsStdout(truth_path)) {
    WriteTextOutput(truth_path, audio::TruthCsv(recording));
  }

  std::map<std::string, int> counts;
  for (const auto& event : recording.events) counts[std::string(ToString(event.kind))]++;
  std::string events;
  for (const auto& [kind, count] : counts) {
    events += fmt::format("{}{} {}", events.empty() ? "" : ", ", count, kind);
  }
  fmt::print(out, "wrote {}: {} Hz, {} channel(s), {:.3f} s, {} {}\n", args.output,
             summary.sample_rate_hz, summary.channels,
             static_cast<double>(summary.frames) / summary.sample_rate_hz,
             ToString(write_options.container), args.format);
  fmt::print(out, "events: {}\n", events.empty() ? "none" : events);
  const auto onsets = recording.BallImpactOnsetsS();
  if (!onsets.empty()) {
    fmt::print(out, "ball impacts from {:.6f} s to {:.6f} s\n", onsets.front(), onsets.back());
  }
  if (recording.chain) {
    const audio::RecordingChainSummary& chain = *recording.chain;
    const double rate_hz = options.sample_rate_hz;
    fmt::print(
        out,
        "recording chain: {} anti-aliasing FIR, {} taps at {:.0f} Hz ({} x {} Hz): passband to "
        "{:.0f} Hz (ripple {:.1e} dB), stop band from {:.0f} Hz ({:.1f} dB)\n",
        ToString(chain.chain.phase), chain.taps, chain.high_rate_hz, chain.chain.oversampling,
        options.sample_rate_hz, chain.chain.passband_edge_fraction * rate_hz,
        chain.passband_ripple_db, chain.chain.stopband_edge_fraction * rate_hz,
        chain.stopband_attenuation_db);
    if (chain.chain.phase == audio::AdcFilterPhase::kLinear) {
      fmt::print(out,
                 "  zero-phase: truth onsets are contact times, and energy reaches up to {:.3f} ms "
                 "before them\n",
                 chain.pre_ring_span_s * 1e3);
    } else {
      fmt::print(out, "  causal: nothing before the truth onsets (contact times)\n");
    }
  }
  if (options.click_gain != 0.0) {
    fmt::print(out, "contact click: half-sine of each contact, peak {} x the impact's peak{}\n",
               options.click_gain, options.chain ? "" : " (sampled without a chain: aliased)");
  }
  if (options.noise) {
    fmt::print(out, "noise rms {:.3g} full scale (SNR {} dB re the {} impact, {} noise)\n",
               recording.noise_rms.front(), options.noise->snr_db, args.snr_reference,
               args.noise_color);
  }
  int clipped = 0;
  for (int count : recording.clipped_sample_count) clipped += count;
  if (clipped > 0) {
    fmt::print(stderr, "note: {} samples clipped at --clip-level {}\n", clipped, *args.clip_level);
  }
  if (summary.clipped_samples > 0) {
    fmt::print(stderr,
               "note: {} samples exceeded full scale and were clipped in the file; lower "
               "--peak-amplitude to avoid it, or write --format float\n",
               summary.clipped_samples);
  }
  if (truth) fmt::print(out, "truth: {}\n", args.truth);
}

}  // namespace

void AddSynthCommand(CLI::App& app) {
  auto args = std::make_shared<SynthArguments>();
  audio::SynthesisOptions& o = args->options;
  auto* command = app.add_subcommand(
      "synth",
      "Render a synthetic bounce recording (ball impacts on plate modes, optional room, noise, "
      "hum, clipping, extra events) with its exact ground truth");
  command->footer(
      "Example:\n  bouncecal synth -o steel.wav --drop-height-m 0.2 --restitution 0.648 "
      "--contact-duration-s 70e-6 --reverb-rt60-s 0.25 --snr-db 35 --seed 1 --truth steel.csv");

  command->add_option("-o,--output", args->output, "Audio file to write: .wav or .flac")
      ->required();
  command->add_option("--truth", args->truth,
                      "Write the ground truth CSV (onset_s,impact_speed_mps,kind,drop,"
                      "peak_amplitude) to this file, - for stdout");
  auto* impacts = command->add_option(
      "--impact-times", args->impact_times,
      "CSV of explicit impacts 'onset_s,impact_speed_mps' (s, m/s) instead of a ballistic drop");
  auto* height = command
                     ->add_option("--drop-height-m", o.drop.drop_height_m,
                                  "Release height above the plate (m)")
                     ->capture_default_str();
  auto* restitution = command
                          ->add_option("--restitution", o.drop.restitution.constant,
                                       "Coefficient of restitution e at zero impact speed "
                                       "(default: sqrt(1 - 0.58), the paper's eta-bar)")
                          ->capture_default_str();
  auto* slope = command
                    ->add_option("--restitution-slope-per-mps", o.drop.restitution.slope_per_mps,
                                 "de/dv: e(v) = restitution + slope * v (s/m; < 0 when e falls "
                                 "with impact speed)")
                    ->capture_default_str();
  auto* drops = command
                    ->add_option("--drops", o.drop.drop_count,
                                 "Number of drops in the file, separated by --drop-gap-s")
                    ->capture_default_str();
  command
      ->add_option("--drop-gap-s", o.drop.gap_between_drops_s,
                   "Silence between a drop's last impact and the next release (s)")
      ->capture_default_str();
  command->add_option("--release-s", o.drop.release_s, "Time the first drop is released (s)")
      ->capture_default_str();
  auto* drag = command->add_option(
      "--terminal-speed-mps", o.drop.terminal_speed_mps,
      "Add quadratic air drag with this terminal speed (m/s): ~9 ping-pong, ~50 steel ball");
  command
      ->add_option("--min-flight-s", o.drop.min_flight_s,
                   "A drop ends when the next flight would be shorter than this (s)")
      ->capture_default_str();
  for (auto* option : {height, restitution, slope, drops, drag}) impacts->excludes(option);

  command->add_option("--sample-rate-hz", o.sample_rate_hz, "Sample rate (Hz)")
      ->capture_default_str();
  command->add_option("--duration-s", o.duration_s, "File length (s); 0 = last event plus --tail-s")
      ->capture_default_str();
  command->add_option("--tail-s", o.tail_s, "Audio kept after the last event (s)")
      ->capture_default_str();
  command->add_option("--gravity-mps2", o.gravity_mps2, "Gravitational acceleration (m/s^2)")
      ->capture_default_str();
  command
      ->add_option("--surface", args->surface,
                   "Mode set: plate (steel plate, 1.2-14 kHz) or counter (ping-pong on a counter, "
                   "1.2-17 kHz, rings 50-250 ms)")
      ->check(CLI::IsMember({"plate", "counter"}))
      ->capture_default_str();
  command
      ->add_option("--contact-duration-s", o.contact_duration_s,
                   "Contact time at 1.98 m/s (s): ~70e-6 steel, ~1e-3 ping-pong")
      ->capture_default_str();
  command
      ->add_option("--peak-amplitude", o.peak_amplitude,
                   "Amplitude scale of an impact at 1.98 m/s (full scale = 1)")
      ->capture_default_str();
  command
      ->add_option("--level-jitter-db", o.level_jitter_db,
                   "Random per-impact level spread, standard deviation (dB)")
      ->capture_default_str();

  command->add_option("--snr-db", args->snr_db,
                      "Add noise at this SNR (dB): window power of the reference impact's direct "
                      "sound (--snr-window-s) over the noise power");
  command->add_option("--noise-color", args->noise_color, "white or pink")
      ->check(CLI::IsMember({"white", "pink"}))
      ->capture_default_str();
  command
      ->add_option("--snr-reference", args->snr_reference,
                   "Impact defining the SNR: first or weakest")
      ->check(CLI::IsMember({"first", "weakest"}))
      ->capture_default_str();
  command
      ->add_option("--snr-window-s", args->snr_window_s,
                   "Window after the reference impact's onset for the SNR signal power (s)")
      ->capture_default_str();
  command->add_option("--reverb-rt60-s", args->reverb_rt60_s,
                      "Add a diffuse room tail decaying 60 dB in this time (s)");
  command
      ->add_option("--reverb-drr-db", args->reverb_drr_db,
                   "Direct-to-reverberant energy ratio of the tail (dB)")
      ->capture_default_str();
  command->add_option("--echo-delay-s", args->echo_delay_s,
                      "Discrete echo delay (s), repeatable, e.g. 0.009");
  command->add_option("--echo-gain-db", args->echo_gain_db,
                      "Gain of each --echo-delay-s echo (dB), e.g. -12");
  command->add_option("--precursor-lead-s", args->precursor_lead_s,
                      "Add a weak click this long before each impact (s), e.g. 0.007");
  command->add_option("--precursor-gain-db", args->precursor_gain_db, "Precursor level (dB)")
      ->capture_default_str();
  command->add_option("--hum-hz", args->hum_hz, "Add mains hum at this fundamental (Hz): 50 or 60");
  command->add_option("--hum-dbfs", args->hum_dbfs, "Hum fundamental peak level (dBFS)")
      ->capture_default_str();
  command
      ->add_option("--hum-harmonics", args->hum_harmonics,
                   "Hum partials including the fundamental (1/k amplitudes)")
      ->capture_default_str();
  command->add_option("--dc-offset", o.dc_offset, "DC offset (full scale)")->capture_default_str();
  command->add_option("--clip-level", args->clip_level,
                      "Hard-clip at +-this level (full scale, 0 < level <= 1)");
  auto* limiter = command->add_option(
      "--limiter-gain-db", args->limiter_gain_db,
      "Record through a phone's gain stage: an AGC's gain (dB, 0-60, e.g. 20; with "
      "--agc-target-dbfs where it starts and its most), then a look-ahead peak limiter");
  command
      ->add_option("--limiter-ceiling-dbfs", args->limiter.ceiling_dbfs,
                   "The limiter's ceiling (dBFS)")
      ->capture_default_str()
      ->needs(limiter);
  command
      ->add_option("--limiter-lookahead-s", args->limiter.lookahead_s,
                   "How far ahead the limiter sees (s)")
      ->capture_default_str()
      ->needs(limiter);
  command
      ->add_option("--limiter-release-s", args->limiter.release_s,
                   "The limiter's release time constant (s)")
      ->capture_default_str()
      ->needs(limiter);
  auto* target = command->add_option(
      "--agc-target-dbfs", args->limiter.target_dbfs,
      "Steer the gain (from --limiter-gain-db, never above it) toward this level (dBFS, RMS over "
      "--agc-level-time-s); unset: the gain stays");
  target->needs(limiter);
  command
      ->add_option("--agc-slew-db-per-s", args->limiter.slew_db_per_s,
                   "How fast the AGC's gain may move (dB/s)")
      ->capture_default_str()
      ->needs(target);
  command
      ->add_option("--agc-level-time-s", args->limiter.level_time_s,
                   "Time constant of the level the AGC steers by (s)")
      ->capture_default_str()
      ->needs(target);
  command->add_option("--band-limit-hz", o.band_limit_hz,
                      "Low-pass everything here like a lossy codec (Hz), e.g. 7000");
  auto* adc =
      command
          ->add_option("--adc", args->adc,
                       "Record through an ADC/resampler chain: render at --adc-oversampling x "
                       "the rate and decimate with a linear-phase (zero-phase: energy before "
                       "each onset) or minimum-phase (causal) anti-aliasing FIR")
          ->check(CLI::IsMember({"linear-phase", "minimum-phase"}));
  command
      ->add_option("--adc-oversampling", args->chain.oversampling,
                   "Rendering rate of the chain as a multiple of the sample rate (2-64; 0 = the "
                   "smallest >= 8 reaching 384 kHz)")
      ->capture_default_str()
      ->needs(adc);
  command
      ->add_option("--adc-passband-fs", args->chain.passband_edge_fraction,
                   "Passband edge of the chain's filter as a fraction of the sample rate")
      ->capture_default_str()
      ->needs(adc);
  command
      ->add_option("--adc-stopband-fs", args->chain.stopband_edge_fraction,
                   "Stop-band edge of the chain's filter as a fraction of the sample rate (0.5: "
                   "alias-free, as resamplers)")
      ->capture_default_str()
      ->needs(adc);
  command
      ->add_option("--adc-stopband-db", args->chain.stopband_attenuation_db,
                   "Stop-band attenuation of the chain's filter (dB, 40-150)")
      ->capture_default_str()
      ->needs(adc);
  command
      ->add_option("--click-gain", o.click_gain,
                   "Add the ball's acceleration noise: a half-sine of each contact peaking at "
                   "this x the impact's peak (e.g. 0.2; aliased without --adc)")
      ->capture_default_str();
  command->add_option("--knock-s", args->knock_s,
                      "Add a knock (not a ball impact) at this time (s), repeatable");
  command->add_option("--thump-s", args->thump_s,
                      "Add a low-frequency handling thump at this time (s), repeatable");
  command->add_option("--stray-s", args->stray_s,
                      "Add a stray 0.3-2.5 kHz noise burst at this time (s), repeatable");
  command
      ->add_option("--event-amplitude", args->event_amplitude,
                   "Peak of knocks, thumps and strays (full scale)")
      ->capture_default_str();
  command
      ->add_option("--leading-silence-s", o.leading_digital_silence_s,
                   "Exact digital zeros at the start (s)")
      ->capture_default_str();
  command->add_option("--channels", args->channels, "Number of channels (microphones)")
      ->capture_default_str();
  command
      ->add_option("--channel-delay-s", args->channel_delay_s,
                   "Channel c hears everything c times this later (s), e.g. 0.00025")
      ->capture_default_str();
  command
      ->add_option("--channel-gain-db", args->channel_gain_db,
                   "Channel c is c times this louder (dB)")
      ->capture_default_str();
  command
      ->add_option("--channel-snr-offset-db", args->channel_snr_offset_db,
                   "Channel c has c times this higher SNR (dB)")
      ->capture_default_str();
  command->add_option("--format", args->format, "Sample encoding: pcm16, pcm24, pcm32 or float")
      ->check(CLI::IsMember({"pcm16", "pcm24", "pcm32", "float"}))
      ->capture_default_str();
  command->add_option("--seed", o.seed, "Seed of every random component")->capture_default_str();
  command->callback([args] { RunSynth(*args); });
}

}  // namespace bouncecal::apps
