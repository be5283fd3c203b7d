#include "bouncecal/audio/synthesize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "bouncecal/error.h"
#include "bouncecal/random_stream.h"
#include "synth/anti_aliasing_filter.h"
#include "synth/band_limit.h"
#include "synth/contact_click.h"
#include "synth/extra_event_sound.h"
#include "synth/limiter.h"
#include "synth/modal_impact.h"
#include "synth/noise.h"
#include "synth/recording_chain.h"
#include "synth/reverb.h"

namespace bouncecal::audio {
namespace {

// Independent random streams (see RandomStream); never renumber, or seeded outputs change.
enum Stream : std::uint64_t {
  kLevelJitterStream = 1,
  kReverbStream = 2,
  kNoiseStream = 3,
  kHumStream = 4,
  kExtraEventStream = 5,
};

double DbToGain(double db) { return std::pow(10.0, db / 20.0); }

std::string Number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// Modes a recorder would actually capture: its anti-aliasing filter removes everything near
// and above Nyquist, and a mode rendered there would alias. Without a chain rate_hz is the
// output rate; with one it is the high rate, and the chain's own filter removes the rest.
std::vector<PlateMode> AudibleModes(std::span<const PlateMode> modes, double rate_hz) {
  std::vector<PlateMode> audible;
  for (const PlateMode& mode : modes) {
    if (mode.frequency_hz < 0.45 * rate_hz && mode.gain != 0) audible.push_back(mode);
  }
  return audible;
}

// Working memory of a chain: one float per high-rate sample of one channel. 2^27 samples
// (512 MiB) is 5.8 minutes at 8 x 48 kHz.
constexpr std::int64_t kMaxHighRateSamples = std::int64_t{1} << 27;

// How one ball impact sounds (before channel gain): contact duration and amplitude scale with
// impact speed (Hertz: tau ~ v^-1/5; impulse ~ v).
struct ImpactVoice {
  double contact_s;
  double scale;
};

// unit_peak: the sampled peak of the mode bank at the reference speed, so that peak_amplitude is
// the actual peak of a reference impact in full-scale units.
ImpactVoice VoiceFor(const SynthesisOptions& options, double unit_peak, double impact_speed_mps,
                     double jitter) {
  const double ratio = impact_speed_mps / options.reference_speed_mps;
  return {options.contact_duration_s * std::pow(ratio, options.contact_duration_speed_exponent),
          options.peak_amplitude / unit_peak * std::pow(ratio, options.amplitude_speed_exponent) *
              jitter};
}

// The peak of an impact comes within the first few periods of the lowest mode; 50 ms covers any
// mode above 100 Hz with margin.
constexpr double kPeakSearchS = 0.05;

// Renders one excitation of the modes (and its contact click when click_peak != 0) at the
// output samples [first_output, first_output + out.size()): directly at sample_rate_hz without
// a chain, else at the chain's high rate through its decimator.
void RenderDirectSound(std::span<const PlateMode> modes, const AntiAliasingFilter* filter,
                       double arrival_s, double scale, double contact_s, double click_peak,
                       double sample_rate_hz, std::int64_t first_output, std::span<float> out) {
  if (filter == nullptr) {
    // Rendered into a buffer whose sample 0 is sample first_output of the file.
    const double arrival_in_out_s = arrival_s - static_cast<double>(first_output) / sample_rate_hz;
    const ModalExcitation excitation{arrival_in_out_s, scale, contact_s};
    RenderModalExcitations(modes, std::span(&excitation, 1), sample_rate_hz, out);
    if (click_peak != 0.0) {
      const ContactClick click{arrival_in_out_s, click_peak, contact_s};
      AddContactClicks(std::span(&click, 1), sample_rate_hz, 0, out);
    }
    return;
  }
  const double high_rate_hz = sample_rate_hz * filter->oversampling;
  const HighRateRange range =
      DecimatorInput(*filter, first_output, static_cast<std::int64_t>(out.size()));
  std::vector<float> high(static_cast<size_t>(range.count), 0.0f);
  const double arrival_in_high_s = arrival_s - static_cast<double>(range.first) / high_rate_hz;
  const ModalExcitation excitation{arrival_in_high_s, scale, contact_s};
  RenderModalExcitations(modes, std::span(&excitation, 1), high_rate_hz, high);
  if (click_peak != 0.0) {
    const ContactClick click{arrival_in_high_s, click_peak, contact_s};
    AddContactClicks(std::span(&click, 1), high_rate_hz, 0, high);
  }
  Decimate(*filter, high, range.first, first_output, out);
}

// The sampled peak of a reference impact (unit scale, onset on a sample) through the chain: with
// a chain, peak_amplitude means the peak of what reaches the file.
double ChainSampledPeak(std::span<const PlateMode> modes, const AntiAliasingFilter& filter,
                        double contact_s, double sample_rate_hz, double span_s) {
  const auto count = static_cast<size_t>(span_s * sample_rate_hz) + 1;
  std::vector<float> rendered(count, 0.0f);
  RenderDirectSound(modes, &filter, 0.0, 1.0, contact_s, 0.0, sample_rate_hz, 0, rendered);
  double peak = 0.0;
  for (float value : rendered) peak = std::max(peak, std::abs(double{value}));
  return peak;
}

// Mean square of one impact's direct sound (with its contact click) over the
// round(window_s * rate) samples that start at the first sample at or after its arrival (a
// sample count, so rounding of t_i never adds or drops a sample at the window's end).
double WindowPower(std::span<const PlateMode> modes, const AntiAliasingFilter* filter,
                   double contact_s, double scale, double click_peak, double arrival_s,
                   double window_s, double sample_rate_hz) {
  const std::int64_t first = FirstSampleAtOrAfter(arrival_s, sample_rate_hz);
  const auto count = std::max<std::int64_t>(1, std::llround(window_s * sample_rate_hz));
  std::vector<float> window(static_cast<size_t>(count), 0.0f);
  RenderDirectSound(modes, filter, arrival_s, scale, contact_s, click_peak, sample_rate_hz, first,
                    window);
  double sum = 0.0;
  for (float value : window) sum += static_cast<double>(value) * value;
  return sum / static_cast<double>(count);
}

// Adds amplitude * sin(omega n + phase) for the file's samples n = first_sample + i. A rotating
// phasor (one complex multiply per sample) re-anchored with sin/cos every 4096 samples keeps the
// phase exact over hours at a fraction of a sin() per sample.
void AddSine(double amplitude, double omega, double phase, std::int64_t first_sample,
             std::span<float> out) {
  constexpr size_t kReanchorSamples = 4096;
  const double step_re = std::cos(omega);
  const double step_im = std::sin(omega);
  for (size_t start = 0; start < out.size(); start += kReanchorSamples) {
    const double angle =
        omega * static_cast<double>(first_sample + static_cast<std::int64_t>(start)) + phase;
    double re = amplitude * std::cos(angle);
    double im = amplitude * std::sin(angle);
    const size_t stop = std::min(out.size(), start + kReanchorSamples);
    for (size_t i = start; i < stop; ++i) {
      out[i] += static_cast<float>(im);
      const double next_re = re * step_re - im * step_im;
      im = re * step_im + im * step_re;
      re = next_re;
    }
  }
}

// A fall from rest through height_m, ballistic or with quadratic drag (see DropSpec).
struct Fall {
  double duration_s;
  double landing_speed_mps;
};
Fall FallFrom(double height_m, double g, std::optional<double> terminal_speed_mps) {
  if (!terminal_speed_mps) return {std::sqrt(2.0 * height_m / g), std::sqrt(2.0 * g * height_m)};
  const double vt = *terminal_speed_mps;
  const double x = g * height_m / (vt * vt);
  // acosh(e^x) = x + ln(1 + sqrt(1 - e^-2x)), written so a high terminal speed (x -> 0) keeps
  // full precision instead of cancelling in acosh(1 + tiny).
  const double root = std::sqrt(-std::expm1(-2.0 * x));
  return {vt / g * (x + std::log1p(root)), vt * root};
}

// A flight launched upwards at launch_mps, back down to the floor.
using Flight = Fall;
Flight FlightFrom(double launch_mps, double g, std::optional<double> terminal_speed_mps) {
  if (!terminal_speed_mps) return {2.0 * launch_mps / g, launch_mps};
  const double vt = *terminal_speed_mps;
  const double rise_s = vt / g * std::atan(launch_mps / vt);
  const double apex_m = vt * vt / (2.0 * g) * std::log1p(launch_mps * launch_mps / (vt * vt));
  const Fall fall = FallFrom(apex_m, g, terminal_speed_mps);
  return {rise_s + fall.duration_s, fall.landing_speed_mps};
}

}  // namespace

std::vector<PlateMode> RectangularPlateModes(const RectangularPlate& plate) {
  const auto require = [](std::string_view name, double value, double lower, double upper) {
    if (std::isfinite(value) && value > lower && value <= upper) return;
    throw ConfigError("plate option " + std::string(name) + " = " + Number(value) +
                      " is outside (" + Number(lower) + ", " + Number(upper) +
                      "]; choose a value in range");
  };
  require("length_m", plate.length_m, 0.0, 100.0);
  require("width_m", plate.width_m, 0.0, 100.0);
  require("thickness_m", plate.thickness_m, 0.0, 1.0);
  require("youngs_modulus_pa", plate.youngs_modulus_pa, 0.0, 1e13);
  require("density_kg_per_m3", plate.density_kg_per_m3, 0.0, 1e5);
  require("poisson_ratio", plate.poisson_ratio, -1.0, 0.5);
  require("loss_factor", plate.loss_factor, 0.0, 1.0);
  for (double fraction : {plate.impact_x_fraction, plate.impact_y_fraction, plate.pickup_x_fraction,
                          plate.pickup_y_fraction}) {
    require("impact/pickup fraction", fraction, 0.0, 1.0);
  }
  require("min_frequency_hz", plate.min_frequency_hz, -1.0, 1e6);
  require("max_frequency_hz", plate.max_frequency_hz, plate.min_frequency_hz, 1e6);
  // Modal density is area / (4 pi) sqrt(rho h / D) per rad/s; refuse plates that would need
  // more modes than any rendering can afford.
  constexpr size_t kMaxModes = 5000;
  const double rigidity = plate.youngs_modulus_pa * std::pow(plate.thickness_m, 3) /
                          (12.0 * (1.0 - plate.poisson_ratio * plate.poisson_ratio));
  const double wave_factor =
      0.5 * std::numbers::pi * std::sqrt(rigidity / (plate.density_kg_per_m3 * plate.thickness_m));
  const auto shape = [](int m, int n, double x, double y) {
    return std::sin(m * std::numbers::pi * x) * std::sin(n * std::numbers::pi * y);
  };
  std::vector<PlateMode> modes;
  double largest = 0.0;
  for (int m = 1;; ++m) {
    if (wave_factor * std::pow(m / plate.length_m, 2) > plate.max_frequency_hz) break;
    for (int n = 1;; ++n) {
      const double frequency_hz =
          wave_factor * (std::pow(m / plate.length_m, 2) + std::pow(n / plate.width_m, 2));
      if (frequency_hz > plate.max_frequency_hz) break;
      if (frequency_hz < plate.min_frequency_hz) continue;
      const double gain = shape(m, n, plate.impact_x_fraction, plate.impact_y_fraction) *
                          shape(m, n, plate.pickup_x_fraction, plate.pickup_y_fraction);
      modes.push_back(
          {frequency_hz, 1.0 / (std::numbers::pi * plate.loss_factor * frequency_hz), gain});
      if (modes.size() > kMaxModes) {
        throw ConfigError("plate options give more than " + std::to_string(kMaxModes) +
                          " modes below max_frequency_hz; use a smaller or thicker plate or a "
                          "lower max_frequency_hz");
      }
      largest = std::max(largest, std::abs(gain));
    }
  }
  std::sort(modes.begin(), modes.end(),
            [](const PlateMode& a, const PlateMode& b) { return a.frequency_hz < b.frequency_hz; });
  if (largest > 0.0) {
    for (PlateMode& mode : modes) mode.gain /= largest;
  }
  return modes;
}

std::vector<PlateMode> SteelPlateModes() { return RectangularPlateModes(RectangularPlate{}); }

std::vector<PlateMode> CounterTopModes() {
  // Matched by eye to the spectrogram of eeps-pingpong/pingpong.wav: dense lines from 1 to 18 kHz
  // with the highest dying within ~50 ms and the rest ringing into the next bounce. What rings
  // there (counter, sink, the ball's shell) is unknown; a plate with these numbers has the same
  // modal density and decays.
  RectangularPlate plate;
  plate.length_m = 0.20;
  plate.width_m = 0.13;
  plate.thickness_m = 0.0012;
  plate.loss_factor = 8e-4;
  plate.impact_x_fraction = 0.23;
  plate.impact_y_fraction = 0.61;
  plate.pickup_x_fraction = 0.71;
  plate.pickup_y_fraction = 0.37;
  plate.min_frequency_hz = 1100.0;
  plate.max_frequency_hz = 18000.0;
  return RectangularPlateModes(plate);
}

std::vector<PlateMode> TableTopModes() {
  RectangularPlate table;
  table.length_m = 0.9;
  table.width_m = 0.6;
  table.thickness_m = 0.018;
  table.youngs_modulus_pa = 10e9;
  table.density_kg_per_m3 = 650.0;
  table.poisson_ratio = 0.3;
  table.loss_factor = 0.02;
  table.min_frequency_hz = 100.0;
  table.max_frequency_hz = 6000.0;
  return RectangularPlateModes(table);
}

double RestitutionLaw::Evaluate(double impact_speed_mps) const {
  if (callback) return callback(impact_speed_mps);
  return constant + slope_per_mps * impact_speed_mps;
}

std::string_view ToString(AdcFilterPhase phase) {
  switch (phase) {
    case AdcFilterPhase::kLinear:
      return "linear-phase";
    case AdcFilterPhase::kMinimum:
      return "minimum-phase";
  }
  return "unknown";
}

std::string_view ToString(SoundEventKind kind) {
  switch (kind) {
    case SoundEventKind::kBallImpact:
      return "ball_impact";
    case SoundEventKind::kPrecursor:
      return "precursor";
    case SoundEventKind::kKnock:
      return "knock";
    case SoundEventKind::kThump:
      return "thump";
    case SoundEventKind::kStray:
      return "stray";
  }
  return "unknown";
}

std::vector<double> SynthesizedRecording::BallImpactOnsetsS(std::optional<int> drop_index) const {
  std::vector<double> onsets;
  for (const SynthesizedEvent& event : events) {
    if (event.kind != SoundEventKind::kBallImpact) continue;
    if (drop_index && event.drop_index != *drop_index) continue;
    onsets.push_back(event.onset_s);
  }
  return onsets;
}

std::vector<SynthesizedEvent> PlanBallImpacts(const SynthesisOptions& options) {
  std::vector<SynthesizedEvent> impacts;
  if (!options.impacts.empty()) {
    for (const ImpactSpec& spec : options.impacts) {
      impacts.push_back(
          {spec.onset_s, SoundEventKind::kBallImpact, spec.impact_speed_mps, spec.drop_index});
    }
    std::sort(impacts.begin(), impacts.end(),
              [](const auto& a, const auto& b) { return a.onset_s < b.onset_s; });
    return impacts;
  }
  const DropSpec& drop = options.drop;
  const double g = options.gravity_mps2;
  double release_s = drop.release_s;
  for (int d = 0; d < drop.drop_count; ++d) {
    const Fall first = FallFrom(drop.drop_height_m, g, drop.terminal_speed_mps);
    double onset_s = release_s + first.duration_s;
    double speed_mps = first.landing_speed_mps;
    for (int k = 0; k < drop.max_impacts_per_drop; ++k) {
      impacts.push_back({onset_s, SoundEventKind::kBallImpact, speed_mps, d});
      const double e = drop.restitution.Evaluate(speed_mps);
      if (!std::isfinite(e) || e <= 0.0 || e >= 1.0) {
        throw ConfigError("synthesis option drop.restitution gives e = " + Number(e) +
                          " at impact speed " + Number(speed_mps) +
                          " m/s; the law must stay inside (0, 1) for every impact speed");
      }
      const Flight flight = FlightFrom(e * speed_mps, g, drop.terminal_speed_mps);
      if (flight.duration_s < drop.min_flight_s) break;
      onset_s += flight.duration_s;
      speed_mps = flight.landing_speed_mps;
    }
    release_s = impacts.back().onset_s + drop.gap_between_drops_s;
  }
  return impacts;
}

namespace {

// What every channel of one recording shares: the impacts and their levels, the recording
// chain's filter and the file's extent, decided once before any channel is rendered.
struct RenderPlan {
  std::vector<SynthesizedEvent> ball_impacts;
  std::vector<double> jitter;        // per ball impact: its level jitter, shared by every channel
  std::vector<double> impact_peaks;  // per ball impact: its peak amplitude at channel gain 0 dB
  std::vector<SynthesizedEvent> events;  // the truth: every event inside the file, in time order
  std::optional<AntiAliasingFilter> filter;
  double acoustic_rate_hz = 0;  // the rate the sound is rendered at (the chain's high rate)
  std::vector<PlateMode> modes;
  double unit_peak = 0;  // sampled peak of a unit reference impact (VoiceFor)
  double duration_s = 0;
  std::int64_t frame_count = 0;
  std::int64_t acoustic_count = 0;            // samples per channel at acoustic_rate_hz
  std::int64_t silence_frames = 0;            // leading digital zeros
  std::vector<double> echo_delays_s = {0.0};  // the direct sound, then each discrete echo
  std::vector<double> echo_gains = {1.0};

  const AntiAliasingFilter* chain_filter() const { return filter ? &*filter : nullptr; }
};

double UnitPeak(const SynthesisOptions& options, const RenderPlan& plan) {
  const double peak =
      plan.filter
          ? ChainSampledPeak(
                plan.modes, *plan.filter, options.contact_duration_s, options.sample_rate_hz,
                std::min(kPeakSearchS,
                         ModalImpact(plan.modes, options.contact_duration_s).ring_duration_s()))
          : ModalImpact(plan.modes, options.contact_duration_s)
                .SampledPeak(options.sample_rate_hz, kPeakSearchS);
  if (!(peak > 0.0)) {
    throw ConfigError(
        "synthesis option modes: the audible modes give a silent impact; give "
        "modes with non-zero gain below 0.45 x sample_rate_hz");
  }
  return peak;
}

// Every ball impact's level (with its jitter) and every event of the truth, before truncation to
// the file's length.
void PlanLevelsAndEvents(const SynthesisOptions& options, RenderPlan& plan) {
  plan.jitter.assign(plan.ball_impacts.size(), 1.0);
  if (options.level_jitter_db > 0.0) {
    RandomStream random(options.seed, kLevelJitterStream);
    for (double& value : plan.jitter) {
      value = DbToGain(options.level_jitter_db * random.Gaussian());
    }
  }
  plan.impact_peaks.resize(plan.ball_impacts.size());
  for (size_t k = 0; k < plan.ball_impacts.size(); ++k) {
    SynthesizedEvent impact = plan.ball_impacts[k];
    impact.peak_amplitude = options.peak_amplitude *
                            std::pow(impact.impact_speed_mps / options.reference_speed_mps,
                                     options.amplitude_speed_exponent) *
                            plan.jitter[k];
    plan.impact_peaks[k] = impact.peak_amplitude;
    plan.events.push_back(impact);
    if (options.precursor) {
      plan.events.push_back({impact.onset_s - options.precursor->lead_s, SoundEventKind::kPrecursor,
                             impact.impact_speed_mps, impact.drop_index,
                             impact.peak_amplitude * DbToGain(options.precursor->gain_db)});
    }
  }
  for (const ExtraEvent& extra : options.extra_events) {
    plan.events.push_back({extra.onset_s, extra.kind, 0.0, -1, extra.peak_amplitude});
  }
  std::stable_sort(plan.events.begin(), plan.events.end(),
                   [](const auto& a, const auto& b) { return a.onset_s < b.onset_s; });
}

// The file's length, and the events it holds; refuses a file that would be empty, too long for
// the chain's high-rate buffer, or that starts after an event.
void PlanExtent(const SynthesisOptions& options, RenderPlan& plan) {
  const double rate_hz = options.sample_rate_hz;
  double max_delay_s = 0.0;
  for (const ChannelOptions& channel : options.channels) {
    max_delay_s = std::max(max_delay_s, channel.delay_s);
  }
  plan.duration_s =
      options.duration_s > 0.0
          ? options.duration_s
          : (plan.events.empty() ? 0.0 : plan.events.back().onset_s) + max_delay_s + options.tail_s;
  plan.frame_count = static_cast<std::int64_t>(std::ceil(plan.duration_s * rate_hz));
  if (plan.frame_count < 1) {
    throw ConfigError(
        "synthesis option duration_s gives an empty recording; set duration_s or "
        "tail_s above 0");
  }
  std::erase_if(plan.events,
                [&](const SynthesizedEvent& event) { return event.onset_s >= plan.duration_s; });
  // With a chain the high-rate signal runs on past the last output sample by the filter's lead.
  const HighRateRange acoustic_range = plan.filter
                                           ? DecimatorInput(*plan.filter, 0, plan.frame_count)
                                           : HighRateRange{0, plan.frame_count};
  plan.acoustic_count = acoustic_range.first + acoustic_range.count;
  if (plan.filter && plan.acoustic_count > kMaxHighRateSamples) {
    throw ConfigError(
        "synthesis option chain: " + Number(plan.duration_s) + " s at " +
        std::to_string(plan.filter->oversampling) + " x " + std::to_string(options.sample_rate_hz) +
        " Hz needs " + std::to_string(plan.acoustic_count) +
        " high-rate samples per channel, more than " + std::to_string(kMaxHighRateSamples) +
        "; lower chain.oversampling or render a shorter file");
  }
  for (const SynthesizedEvent& event : plan.events) {
    if (event.onset_s < options.leading_digital_silence_s) {
      throw ConfigError("synthesis option leading_digital_silence_s = " +
                        Number(options.leading_digital_silence_s) + " s hides the " +
                        std::string(ToString(event.kind)) + " at " + Number(event.onset_s) +
                        " s; make the silence end before the first event");
    }
    if (event.onset_s < 0.0) {
      throw ConfigError("synthesis: the " + std::string(ToString(event.kind)) + " at " +
                        Number(event.onset_s) +
                        " s falls before the start of the file; start the drop later");
    }
  }
  plan.silence_frames = std::min<std::int64_t>(
      plan.frame_count,
      static_cast<std::int64_t>(std::ceil(options.leading_digital_silence_s * rate_hz)));
}

RenderPlan PlanRecording(const SynthesisOptions& options) {
  RenderPlan plan;
  plan.ball_impacts = PlanBallImpacts(options);
  if (options.chain) plan.filter = DesignAntiAliasingFilter(*options.chain, options.sample_rate_hz);
  plan.acoustic_rate_hz =
      plan.filter ? options.sample_rate_hz * plan.filter->oversampling : options.sample_rate_hz;
  plan.modes = AudibleModes(options.modes, plan.acoustic_rate_hz);
  plan.unit_peak = UnitPeak(options, plan);
  PlanLevelsAndEvents(options, plan);
  PlanExtent(options, plan);
  if (options.reverb) {
    for (const Echo& echo : options.reverb->echoes) {
      plan.echo_delays_s.push_back(echo.delay_s);
      plan.echo_gains.push_back(DbToGain(echo.gain_db));
    }
  }
  return plan;
}

// Renders what reaches channel c's microphone (every ball impact with its echoes, precursor and
// click, the extra events, the room's tail) into `acoustic` at the plan's acoustic rate. Returns
// each ball impact's direct-sound window power, which sets the noise level for the SNR.
std::vector<double> RenderSound(const SynthesisOptions& options, const RenderPlan& plan, size_t c,
                                std::span<float> acoustic) {
  const ChannelOptions& channel = options.channels[c];
  const double channel_gain = DbToGain(channel.gain_db);
  std::vector<double> direct_power;
  std::vector<ModalExcitation> excitations;
  std::vector<ContactClick> clicks;
  for (size_t k = 0; k < plan.ball_impacts.size(); ++k) {
    const SynthesizedEvent& impact = plan.ball_impacts[k];
    if (impact.onset_s >= plan.duration_s) break;
    const ImpactVoice voice =
        VoiceFor(options, plan.unit_peak, impact.impact_speed_mps, plan.jitter[k]);
    const double arrival_s = impact.onset_s + channel.delay_s;
    const double scale = voice.scale * channel_gain;
    const double click_peak = options.click_gain * plan.impact_peaks[k] * channel_gain;
    for (size_t e = 0; e < plan.echo_delays_s.size(); ++e) {
      excitations.push_back(
          {arrival_s + plan.echo_delays_s[e], scale * plan.echo_gains[e], voice.contact_s});
      if (click_peak != 0.0) {
        clicks.push_back(
            {arrival_s + plan.echo_delays_s[e], click_peak * plan.echo_gains[e], voice.contact_s});
      }
      if (options.precursor) {
        excitations.push_back({arrival_s + plan.echo_delays_s[e] - options.precursor->lead_s,
                               scale * plan.echo_gains[e] * DbToGain(options.precursor->gain_db),
                               voice.contact_s});
      }
    }
    if (options.noise) {
      direct_power.push_back(WindowPower(plan.modes, plan.chain_filter(), voice.contact_s, scale,
                                         click_peak, arrival_s, options.noise->window_s,
                                         options.sample_rate_hz));
    }
  }
  RenderModalExcitations(plan.modes, excitations, plan.acoustic_rate_hz, acoustic);
  if (!clicks.empty()) AddContactClicks(clicks, plan.acoustic_rate_hz, 0, acoustic);
  for (size_t i = 0; i < options.extra_events.size(); ++i) {
    const ExtraEvent& extra = options.extra_events[i];
    // Past the file's end an event is not in the truth; with a chain its pre-ringing could
    // otherwise reach the last samples (without one it would write nothing anyway).
    if (plan.filter && extra.onset_s >= plan.duration_s) continue;
    for (size_t e = 0; e < plan.echo_delays_s.size(); ++e) {
      AddExtraEventSound(extra.kind, extra.onset_s + channel.delay_s + plan.echo_delays_s[e],
                         extra.peak_amplitude * channel_gain * plan.echo_gains[e],
                         plan.acoustic_rate_hz, RandomStream(options.seed, kExtraEventStream, i), 0,
                         acoustic);
    }
  }
  if (options.reverb && options.reverb->rt60_s > 0.0) {
    AddConvolution(DiffuseTail(*options.reverb, plan.acoustic_rate_hz,
                               RandomStream(options.seed, kReverbStream, c)),
                   acoustic);
  }
  return direct_power;
}

struct ChannelImpairments {
  double noise_rms = 0;
  int clipped = 0;
};

// What the recording device adds to channel c after the sound reached it: noise at the
// channel's SNR, hum, DC, clipping and a codec's band limit, none of it inside the leading
// digital silence.
ChannelImpairments AddDeviceImpairments(const SynthesisOptions& options, const RenderPlan& plan,
                                        size_t c, std::span<const double> direct_power,
                                        std::span<float> out) {
  const double rate_hz = options.sample_rate_hz;
  ChannelImpairments result;
  std::span<float> live = out.subspan(static_cast<size_t>(plan.silence_frames));
  if (options.noise && !direct_power.empty()) {
    const double reference_power =
        options.noise->reference == SnrReference::kFirstImpact
            ? direct_power.front()
            : *std::min_element(direct_power.begin(), direct_power.end());
    const double snr_db = options.noise->snr_db + options.channels[c].snr_offset_db;
    result.noise_rms = std::sqrt(reference_power / std::pow(10.0, snr_db / 10.0));
    AddNoise(options.noise->color, result.noise_rms, RandomStream(options.seed, kNoiseStream, c),
             live);
  }
  if (options.hum) {
    RandomStream random(options.seed, kHumStream, c);
    const double amplitude = DbToGain(options.hum->fundamental_dbfs);
    for (int h = 1; h <= options.hum->harmonics_count; ++h) {
      const double frequency_hz = h * options.hum->frequency_hz;
      const double phase = 2.0 * std::numbers::pi * random.Uniform();
      if (frequency_hz >= 0.45 * rate_hz) continue;
      const double omega = 2.0 * std::numbers::pi * frequency_hz / rate_hz;
      AddSine(amplitude / h, omega, phase, plan.silence_frames, live);
    }
  }
  if (options.dc_offset != 0.0) {
    for (float& sample : live) sample += static_cast<float>(options.dc_offset);
  }
  if (options.limiter) ApplyLimiter(*options.limiter, rate_hz, live);
  if (options.clip_level) {
    const auto level = static_cast<float>(*options.clip_level);
    for (float& sample : out) {
      if (std::abs(sample) >= level) {
        sample = std::copysign(level, sample);
        ++result.clipped;
      }
    }
  }
  if (options.band_limit_hz) {
    BandLimit(*options.band_limit_hz, 0.1 * *options.band_limit_hz, rate_hz, out);
    std::fill(out.begin(), out.begin() + plan.silence_frames, 0.0f);
  }
  return result;
}

std::optional<RecordingChainSummary> SummariseChain(const SynthesisOptions& options,
                                                    const RenderPlan& plan) {
  if (!plan.filter) return std::nullopt;
  const AntiAliasingFilter& filter = *plan.filter;
  RecordingChain chain = *options.chain;
  chain.oversampling = filter.oversampling;
  return RecordingChainSummary{.chain = chain,
                               .taps = static_cast<int>(filter.taps.size()),
                               .high_rate_hz = plan.acoustic_rate_hz,
                               .kaiser_beta = filter.kaiser_beta,
                               .passband_ripple_db = filter.figures.passband_ripple_db,
                               .stopband_attenuation_db = filter.figures.stopband_attenuation_db,
                               .pre_ring_span_s = filter.lead / plan.acoustic_rate_hz};
}

}  // namespace

SynthesizedRecording SynthesizeBounces(const SynthesisOptions& options) {
  ValidateSynthesisOptions(options);
  RenderPlan plan = PlanRecording(options);
  SynthesizedRecording result;
  for (size_t c = 0; c < options.channels.size(); ++c) {
    Recording recording;
    recording.sample_rate_hz = options.sample_rate_hz;
    recording.source_channel = static_cast<int>(c);
    recording.source_channel_count = static_cast<int>(options.channels.size());
    recording.samples.assign(static_cast<size_t>(plan.frame_count), 0.0f);
    std::span<float> out(recording.samples);
    std::vector<double> direct_power;
    if (plan.filter) {
      // The sound at the chain's high rate, from time 0 (nothing sounds before it), decimated
      // into the file; released before the next channel's.
      std::vector<float> high_rate(static_cast<size_t>(plan.acoustic_count), 0.0f);
      direct_power = RenderSound(options, plan, c, high_rate);
      Decimate(*plan.filter, high_rate, 0, 0, out);
      // Digital silence stays exact zeros, even where an event just after it pre-rings.
      std::fill(out.begin(), out.begin() + plan.silence_frames, 0.0f);
    } else {
      direct_power = RenderSound(options, plan, c, out);
    }
    const ChannelImpairments impairments =
        AddDeviceImpairments(options, plan, c, direct_power, out);
    result.channels.push_back(std::move(recording));
    result.noise_rms.push_back(impairments.noise_rms);
    result.clipped_sample_count.push_back(impairments.clipped);
    result.channel_delay_s.push_back(options.channels[c].delay_s);
  }
  result.events = std::move(plan.events);
  result.click_gain = options.click_gain;
  result.chain = SummariseChain(options, plan);
  return result;
}

std::string TruthCsv(const SynthesizedRecording& recording) {
  std::ostringstream out;
  if (recording.chain) {
    const RecordingChainSummary& chain = *recording.chain;
    out << "# recording chain: " << ToString(chain.chain.phase) << " anti-aliasing FIR, "
        << chain.taps << " taps at " << Number(chain.high_rate_hz) << " Hz ("
        << chain.chain.oversampling << " x the file rate), passband to "
        << Number(chain.chain.passband_edge_fraction) << " fs (ripple "
        << Number(chain.passband_ripple_db) << " dB), stop band from "
        << Number(chain.chain.stopband_edge_fraction) << " fs ("
        << Number(chain.stopband_attenuation_db) << " dB)\n";
    out << (chain.chain.phase == AdcFilterPhase::kLinear
                ? "# onsets are contact times; the zero-phase filter spreads energy up to " +
                      Number(chain.pre_ring_span_s) + " s before them\n"
                : std::string("# onsets are contact times; the causal filter puts nothing before "
                              "them\n"));
  }
  if (recording.click_gain != 0.0) {
    out << "# contact click: half-sine of each impact's contact duration, peak "
        << Number(recording.click_gain) << " x its peak_amplitude\n";
  }
  out << "onset_s,impact_speed_mps,kind,drop,peak_amplitude\n";
  out.setf(std::ios::fixed);
  for (const SynthesizedEvent& event : recording.events) {
    out.precision(9);
    out << event.onset_s << ',';
    out.precision(6);
    out << event.impact_speed_mps << ',' << ToString(event.kind) << ',' << event.drop_index << ','
        << event.peak_amplitude << '\n';
  }
  return out.str();
}

}  // namespace bouncecal::audio
