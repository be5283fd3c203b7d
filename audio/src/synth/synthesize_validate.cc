// Validation of SynthesisOptions: every message is one line naming the option, its value, the
// valid range and what to do.
#include <cmath>
#include <sstream>
#include <string>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

std::string Number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// Throws unless lower <= value <= upper (and finite).
void RequireRange(std::string_view name, double value, double lower, double upper,
                  std::string_view unit) {
  if (std::isfinite(value) && value >= lower && value <= upper) return;
  throw ConfigError("synthesis option " + std::string(name) + " = " + Number(value) +
                    " is outside [" + Number(lower) + ", " + Number(upper) + "]" +
                    (unit.empty() ? "" : " " + std::string(unit)) + "; choose a value in range");
}

// Throws unless lower < value <= upper (and finite).
void RequireAbove(std::string_view name, double value, double lower, double upper,
                  std::string_view unit) {
  if (std::isfinite(value) && value > lower && value <= upper) return;
  throw ConfigError("synthesis option " + std::string(name) + " = " + Number(value) +
                    " is outside (" + Number(lower) + ", " + Number(upper) + "]" +
                    (unit.empty() ? "" : " " + std::string(unit)) + "; choose a value in range");
}

}  // namespace

void ValidateSynthesisOptions(const SynthesisOptions& options) {
  RequireRange("sample_rate_hz", options.sample_rate_hz, 8000, 384000, "Hz");
  const double nyquist_hz = 0.5 * options.sample_rate_hz;
  // Four hours of audio: beyond that a single in-memory buffer per channel is the wrong tool.
  RequireRange("duration_s", options.duration_s, 0.0, 4 * 3600.0, "s (0 = automatic)");
  RequireRange("tail_s", options.tail_s, 0.0, 600.0, "s");
  RequireAbove("gravity_mps2", options.gravity_mps2, 0.0, 1000.0, "m/s^2");

  for (size_t i = 0; i < options.impacts.size(); ++i) {
    const std::string name = "impacts[" + std::to_string(i) + "]";
    RequireRange(name + ".onset_s", options.impacts[i].onset_s, 0.0, 4 * 3600.0, "s");
    RequireAbove(name + ".impact_speed_mps", options.impacts[i].impact_speed_mps, 0.0, 1000.0,
                 "m/s");
    RequireRange(name + ".drop_index", options.impacts[i].drop_index, 0, 1e6, "");
  }
  if (options.impacts.empty()) {
    const DropSpec& drop = options.drop;
    RequireAbove("drop.drop_height_m", drop.drop_height_m, 0.0, 100.0, "m");
    RequireRange("drop.release_s", drop.release_s, 0.0, 3600.0, "s");
    RequireRange("drop.drop_count", drop.drop_count, 1, 1000, "");
    RequireRange("drop.gap_between_drops_s", drop.gap_between_drops_s, 0.0, 3600.0, "s");
    RequireAbove("drop.min_flight_s", drop.min_flight_s, 0.0, 10.0, "s");
    RequireRange("drop.max_impacts_per_drop", drop.max_impacts_per_drop, 1, 100000, "");
    if (drop.terminal_speed_mps) {
      RequireAbove("drop.terminal_speed_mps", *drop.terminal_speed_mps, 0.1, 1e4, "m/s");
    }
    if (!drop.restitution.callback) {
      RequireAbove("drop.restitution.constant", drop.restitution.constant, 0.0, 1.0, "");
      RequireRange("drop.restitution.slope_per_mps", drop.restitution.slope_per_mps, -10.0, 10.0,
                   "s/m");
    }
  }

  RequireAbove("contact_duration_s", options.contact_duration_s, 0.0, 0.1, "s");
  RequireRange("contact_duration_speed_exponent", options.contact_duration_speed_exponent, -1.0,
               1.0, "");
  RequireAbove("reference_speed_mps", options.reference_speed_mps, 0.0, 1000.0, "m/s");
  RequireAbove("peak_amplitude", options.peak_amplitude, 0.0, 100.0, "full scale");
  RequireRange("amplitude_speed_exponent", options.amplitude_speed_exponent, 0.0, 3.0, "");
  RequireRange("level_jitter_db", options.level_jitter_db, 0.0, 20.0, "dB");
  if (options.modes.empty()) {
    throw ConfigError("synthesis option modes is empty; give at least one plate mode");
  }
  bool any_audible = false;
  for (size_t i = 0; i < options.modes.size(); ++i) {
    const std::string name = "modes[" + std::to_string(i) + "]";
    RequireAbove(name + ".frequency_hz", options.modes[i].frequency_hz, 0.0, 200000.0, "Hz");
    RequireAbove(name + ".decay_s", options.modes[i].decay_s, 0.0, 10.0, "s");
    RequireRange(name + ".gain", options.modes[i].gain, -1000.0, 1000.0, "");
    any_audible |= options.modes[i].frequency_hz < 0.9 * nyquist_hz && options.modes[i].gain != 0;
  }
  if (!any_audible) {
    throw ConfigError(
        "synthesis option modes: no mode with non-zero gain lies below 0.9 x the "
        "Nyquist frequency (" +
        Number(0.9 * nyquist_hz) + " Hz); raise sample_rate_hz or add lower modes");
  }

  if (options.reverb) {
    const ReverbOptions& reverb = *options.reverb;
    RequireRange("reverb.rt60_s", reverb.rt60_s, 0.0, 10.0, "s (0 = echoes only)");
    RequireRange("reverb.direct_to_reverberant_db", reverb.direct_to_reverberant_db, -20.0, 80.0,
                 "dB");
    RequireRange("reverb.predelay_s", reverb.predelay_s, 0.0, 1.0, "s");
    for (size_t i = 0; i < reverb.echoes.size(); ++i) {
      const std::string name = "reverb.echoes[" + std::to_string(i) + "]";
      RequireAbove(name + ".delay_s", reverb.echoes[i].delay_s, 0.0, 1.0, "s");
      RequireRange(name + ".gain_db", reverb.echoes[i].gain_db, -120.0, 0.0, "dB");
    }
  }
  if (options.precursor) {
    RequireAbove("precursor.lead_s", options.precursor->lead_s, 0.0, 0.1, "s");
    RequireRange("precursor.gain_db", options.precursor->gain_db, -120.0, 0.0, "dB");
  }
  if (options.noise) {
    RequireRange("noise.snr_db", options.noise->snr_db, -20.0, 140.0, "dB");
    RequireAbove("noise.window_s", options.noise->window_s, 0.0, 1.0, "s");
    if (options.noise->window_s * options.sample_rate_hz < 4.0) {
      throw ConfigError("synthesis option noise.window_s = " + Number(options.noise->window_s) +
                        " s spans fewer than 4 samples; use a window of at least 4 / "
                        "sample_rate_hz");
    }
  }
  if (options.hum) {
    RequireAbove("hum.frequency_hz", options.hum->frequency_hz, 0.0, 0.45 * options.sample_rate_hz,
                 "Hz");
    RequireRange("hum.fundamental_dbfs", options.hum->fundamental_dbfs, -200.0, 0.0, "dBFS");
    RequireRange("hum.harmonics_count", options.hum->harmonics_count, 1, 50, "");
  }
  for (size_t i = 0; i < options.extra_events.size(); ++i) {
    const ExtraEvent& event = options.extra_events[i];
    const std::string name = "extra_events[" + std::to_string(i) + "]";
    if (event.kind != SoundEventKind::kKnock && event.kind != SoundEventKind::kThump &&
        event.kind != SoundEventKind::kStray) {
      throw ConfigError("synthesis option " + name +
                        ".kind = " + std::string(ToString(event.kind)) +
                        " is not an extra event; use knock, thump or stray");
    }
    RequireRange(name + ".onset_s", event.onset_s, 0.0, 4 * 3600.0, "s");
    RequireAbove(name + ".peak_amplitude", event.peak_amplitude, 0.0, 100.0, "full scale");
  }
  RequireRange("dc_offset", options.dc_offset, -1.0, 1.0, "full scale");
  if (options.limiter) {
    const LimiterOptions& limiter = *options.limiter;
    RequireRange("limiter.gain_db", limiter.gain_db, 0.0, 60.0, "dB");
    RequireRange("limiter.ceiling_dbfs", limiter.ceiling_dbfs, -40.0, 0.0, "dBFS");
    RequireRange("limiter.lookahead_s", limiter.lookahead_s, 0.0, 0.02, "s");
    RequireRange("limiter.release_s", limiter.release_s, 1e-3, 5.0, "s");
    if (limiter.target_dbfs) {
      RequireRange("limiter.target_dbfs", *limiter.target_dbfs, -60.0, 0.0, "dBFS");
      RequireRange("limiter.slew_db_per_s", limiter.slew_db_per_s, 0.1, 1000.0, "dB/s");
      RequireRange("limiter.level_time_s", limiter.level_time_s, 1e-3, 5.0, "s");
    }
  }
  if (options.clip_level) RequireAbove("clip_level", *options.clip_level, 0.0, 1.0, "full scale");
  if (options.band_limit_hz) {
    RequireRange("band_limit_hz", *options.band_limit_hz, 500.0, 0.45 * options.sample_rate_hz,
                 "Hz");
  }
  RequireRange("leading_digital_silence_s", options.leading_digital_silence_s, 0.0, 3600.0, "s");
  RequireRange("click_gain", options.click_gain, -10.0, 10.0, "x the impact's peak");
  if (options.chain) {
    const RecordingChain& chain = *options.chain;
    if (chain.oversampling == 1) {
      throw ConfigError(
          "synthesis option chain.oversampling = 1 leaves nothing to decimate, so there is no "
          "anti-aliasing filter to model; use 2 or more (0 = automatic, >= 384 kHz), or "
          "band_limit_hz for a filter at the output rate");
    }
    RequireRange("chain.oversampling", chain.oversampling, 0, 64, "(0 = automatic)");
    RequireAbove("chain.passband_edge_fraction", chain.passband_edge_fraction, 0.05, 0.49,
                 "x sample_rate_hz");
    const double passband = chain.passband_edge_fraction;
    if (!(std::isfinite(chain.stopband_edge_fraction) &&
          chain.stopband_edge_fraction > passband + 0.005 &&
          chain.stopband_edge_fraction <= 1.0 - passband)) {
      throw ConfigError("synthesis option chain.stopband_edge_fraction = " +
                        Number(chain.stopband_edge_fraction) +
                        " must lie above passband_edge_fraction + 0.005 and at most 1 - "
                        "passband_edge_fraction (" +
                        Number(1.0 - passband) +
                        ", beyond which aliases fall into the passband); choose a value in range");
    }
    RequireRange("chain.stopband_attenuation_db", chain.stopband_attenuation_db, 40.0, 150.0, "dB");
  }

  if (options.channels.empty() || options.channels.size() > 64) {
    throw ConfigError("synthesis option channels has " + std::to_string(options.channels.size()) +
                      " entries; give 1 to 64 channels");
  }
  for (size_t i = 0; i < options.channels.size(); ++i) {
    const std::string name = "channels[" + std::to_string(i) + "]";
    RequireRange(name + ".delay_s", options.channels[i].delay_s, 0.0, 1.0, "s");
    RequireRange(name + ".gain_db", options.channels[i].gain_db, -60.0, 40.0, "dB");
    RequireRange(name + ".snr_offset_db", options.channels[i].snr_offset_db, -60.0, 60.0, "dB");
  }
}

}  // namespace bouncecal::audio
