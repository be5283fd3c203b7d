#ifndef BOUNCECAL_AUDIO_SYNTHESIZE_H_
#define BOUNCECAL_AUDIO_SYNTHESIZE_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/audio/recording.h"

namespace bouncecal::audio {

// Synthetic bounce recordings with exact ground truth, for detector tests, calibration round
// trips (dem::SimulateDrop -> SynthesizeBounces -> detect -> calibrate) and the shipped samples.
//
// Each ball impact is a half-sine contact force of duration tau (the Hertz/linear-spring contact
// pulse, Johnson 1985 "Contact Mechanics" ch. 11) driving a bank of independent, exponentially
// decaying plate modes (modal synthesis, van den Doel & Pai 1998). The response of every mode to
// the half-sine is evaluated in closed form at each sample time t_i - t_onset, so an onset is
// never rounded to a sample: shifting an onset by a fraction of a sample shifts the rendered
// waveform by exactly that much. The onset is the START of contact.
//
// All times are in seconds from the first sample of the file, amplitudes in full-scale units
// (+-1 is digital full scale), levels in dB. Everything random is drawn from one seed through
// independent streams per component and channel, so enabling hum does not change the noise.

// One decaying mode of the struck plate: impulse response gain * exp(-t / decay_s) *
// sin(2 pi frequency_hz t). decay_s is the amplitude time constant (T60 = 6.91 decay_s); a
// negative gain is a mode whose shape has opposite signs at the impact and pickup points.
struct PlateMode {
  double frequency_hz = 1000.0;
  double decay_s = 0.1;
  double gain = 1.0;
};

// A thin, simply supported rectangular plate (Kirchhoff theory; Leissa 1969, "Vibration of
// Plates", NASA SP-160): mode (m, n) rings at
//   f_mn = (pi / 2) sqrt(D / (rho h)) ((m / a)^2 + (n / b)^2),  D = E h^3 / (12 (1 - nu^2)),
// with shape sin(m pi x / a) sin(n pi y / b), so a unit impulse at (x0, y0) heard at (x1, y1)
// gives the mode the gain shape(x0, y0) shape(x1, y1) (gains are then scaled to a largest
// |gain| of 1). A constant loss factor eta gives the decay time 1 / (pi eta f): high modes die
// first, as every recording of a struck plate shows.
struct RectangularPlate {
  double length_m = 0.15;  // a
  double width_m = 0.10;   // b
  double thickness_m = 0.001;
  double youngs_modulus_pa = 200e9;  // steel
  double density_kg_per_m3 = 7800.0;
  double poisson_ratio = 0.29;
  double loss_factor = 1e-3;        // decays 320 ms at 1 kHz, 21 ms at 15 kHz
  double impact_x_fraction = 0.37;  // where the ball hits, as fractions of a and b
  double impact_y_fraction = 0.43;
  double pickup_x_fraction = 0.61;  // the plate point whose motion the microphone hears most
  double pickup_y_fraction = 0.29;
  double min_frequency_hz = 1000.0;  // modes kept
  double max_frequency_hz = 15000.0;
};
std::vector<PlateMode> RectangularPlateModes(const RectangularPlate& plate);

// RectangularPlateModes of the default RectangularPlate: a 15 x 10 cm, 1 mm steel plate
// (61 modes from 1.07 to 14.6 kHz, 22-300 ms decays), the default of SynthesisOptions.
std::vector<PlateMode> SteelPlateModes();
// A ping-pong ball on a kitchen counter, modelled on eeps-pingpong/pingpong.wav: dense modes
// from 1.3 to 17.7 kHz (109 of them) ringing 22-300 ms, long enough to overlap the next bounce (a
// 20 x 13 cm, 1.2 mm plate with loss factor 8e-4). The recorded bandwidth (up to 18 kHz) implies an
// excitation much sharper than the ~1 ms ball contact: a half-sine's spectrum has its first
// zero at 1.5 / tau, so use a contact_duration_s of ~50 us to reproduce it.
std::vector<PlateMode> CounterTopModes();
// A wooden table top, the surface of a light or soft ball: a 0.9 x 0.6 m, 18 mm plate (E = 10 GPa,
// 650 kg/m^3, Poisson 0.3, loss factor 0.02, typical of wood: Wegst, "Wood for sound", Am. J. Bot.
// 93(10), 2006): 64 modes from 135 Hz to 6 kHz ringing 3-120 ms. Where a steel plate's modes start
// at 1 kHz, a table's lowest ones ring at a few hundred Hz and carry a soft contact's energy, and
// the ringing that a later bounce lands in is low and slow.
std::vector<PlateMode> TableTopModes();

// Restitution as a function of impact speed: e(v) = constant + slope_per_mps * v, or a user
// callback when `callback` is set (it then wins). The result must stay inside (0, 1) for every
// impact speed that occurs, otherwise SynthesizeBounces throws ConfigError.
struct RestitutionLaw {
  // The paper's eta-bar = 0.58 (1 cm steel ball on copper): e = sqrt(1 - 0.58).
  double constant = 0.648074069840786;
  // de/dv in s/m; negative when e falls with impact speed (the usual case for viscoelastic
  // contacts, Brilliantov et al. 1996; Fr4nci and ub-mth337 recordings show it).
  double slope_per_mps = 0.0;
  std::function<double(double impact_speed_mps)> callback;

  double Evaluate(double impact_speed_mps) const;
};

// A ball impact given explicitly (for example by a DEM simulation).
struct ImpactSpec {
  double onset_s = 0.0;           // start of contact
  double impact_speed_mps = 1.0;  // normal speed just before contact, > 0
  int drop_index = 0;             // which drop it belongs to (truth only), >= 0
};

// Ballistic drops: a ball released from rest at drop_height_m at release_s hits the floor at
// t_1 = release_s + sqrt(2 h0 / g) with v_1 = sqrt(2 g h0); after impact k it leaves with
// e(v_k) v_k and flies dt_k = 2 e(v_k) v_k / g (drag and contact time neglected, as in
// docs/physics.md section 1). A drop ends when the next flight would be shorter than
// min_flight_s (the ball then chatters and rolls) or after max_impacts_per_drop impacts.
//
// With terminal_speed_mps set, flights follow quadratic air drag (m dv/dt = -m g -+ m g v|v| /
// v_t^2) in closed form: rising from u the ball stops after (v_t / g) atan(u / v_t) at
// H = (v_t^2 / 2g) ln(1 + u^2 / v_t^2), then falls for (v_t / g) acosh(exp(g H / v_t^2)) and
// lands at v_t sqrt(1 - exp(-2 g H / v_t^2)). Drag shortens flights, so an analysis that
// assumes ballistic flights reads a lower e (what the Fr4nci authors blame for their h0 fit).
// A ping-pong ball has v_t ~ 9 m/s, a 1 cm steel ball ~ 50 m/s.
struct DropSpec {
  double drop_height_m = 0.20;
  double release_s = 0.3;
  int drop_count = 1;
  // Silence between the last impact of one drop and the release of the next.
  double gap_between_drops_s = 1.0;
  double min_flight_s = 0.005;
  int max_impacts_per_drop = 100;
  RestitutionLaw restitution;
  std::optional<double> terminal_speed_mps;  // unset: no drag
};

// Discrete room echo (an image source): a copy of every sound delayed by delay_s at gain_db.
struct Echo {
  double delay_s = 0.009;
  double gain_db = -12.0;
};

// Diffuse room reverb: each channel's dry sound is convolved with an exponentially decaying
// Gaussian noise tail (Schroeder's statistical reverb model) that starts predelay_s after the
// direct sound and falls by 60 dB in rt60_s. direct_to_reverberant_db is the energy ratio of the
// direct impulse (1) to the whole tail. rt60_s = 0 leaves out the diffuse tail (echoes only).
struct ReverbOptions {
  double rt60_s = 0.3;
  double direct_to_reverberant_db = 10.0;
  double predelay_s = 0.002;
  std::vector<Echo> echoes;  // rendered exactly (analytic, fractional delays)
};

// A weak click lead_s before each ball impact (seen 5-10 ms before the main burst in the eeps
// ping-pong and basketball recordings). It is listed in the truth as kPrecursor; the impact onset
// stays the start of the main burst.
struct PrecursorOptions {
  double lead_s = 0.007;
  double gain_db = -20.0;
};

enum class NoiseColor { kWhite, kPink };

// Which impact defines the signal power of the SNR (see NoiseOptions).
enum class SnrReference { kFirstImpact, kWeakestImpact };

// Additive Gaussian noise at a stated SNR, independent per channel.
//
// SNR definition (the detector's "<= 50 us median at 10 dB SNR" target refers to it):
//   SNR_dB = 10 log10(P_signal / P_noise), where
//   P_signal = mean square, over the round(window_s * sample_rate_hz) samples starting with the
//              first sample at or after the onset, of the DIRECT sound of the reference
//              ball impact alone in that channel (no echoes, reverb, precursor, other impacts,
//              hum or DC), and the reference impact is the first ball impact (kFirstImpact) or
//              the ball impact with the smallest P_signal (kWeakestImpact);
//   P_noise  = mean square of the noise actually added to that channel over the whole file
//              except any leading digital silence (the realisation is rescaled to this power
//              exactly; for pink noise it is the full-band power).
// Hum and DC are not counted as noise.
struct NoiseOptions {
  double snr_db = 35.0;
  NoiseColor color = NoiseColor::kWhite;
  SnrReference reference = SnrReference::kFirstImpact;
  double window_s = 0.005;
};

// Mains hum: a fundamental at frequency_hz (50 or 60 Hz) and harmonics_count - 1 harmonics whose
// amplitude falls as 1/k, with random (seeded) phases.
struct HumOptions {
  double frequency_hz = 50.0;
  double fundamental_dbfs = -40.0;  // peak amplitude of the fundamental, dB re full scale
  int harmonics_count = 5;
};

// A phone's or a recorder's digital gain stage (synth/limiter.h): an automatic gain control
// whose gain starts at gain_db (where it stood in the quiet before the drop) and, with a target,
// is steered at a limited rate toward target_dbfs over the recent level, never above gain_db;
// then a look-ahead peak limiter at the ceiling. Applied after noise, hum and DC, before clipping
// and the band limit.
struct LimiterOptions {
  double gain_db = 20.0;       // the gain at the start and at most, 0 to 60 dB
  double ceiling_dbfs = -1.0;  // no sample leaves louder, -40 to 0 dBFS
  double lookahead_s = 2e-3;   // the limiter sees this far ahead, 0 to 20 ms
  double release_s = 0.06;     // time constant of its recovery, 1 ms to 5 s
  // Unset: the gain stays at gain_db (an AGC that adapts only while its voice detector hears
  // speech).
  std::optional<double> target_dbfs;  // level (RMS over level_time_s) steered to, -60 to 0 dBFS
  double slew_db_per_s = 6.0;         // how fast the gain may move, 0.1 to 1000 dB/s
  double level_time_s = 0.2;          // time constant of that level, 1 ms to 5 s
};

// Non-ball events, listed in the truth with their kind so a detector can be checked for
// rejecting them.
enum class SoundEventKind {
  kBallImpact,
  kPrecursor,
  kKnock,  // a knuckle on the table before the drop: low wooden modes, ~1.5 ms contact
  kThump,  // handling thump: a 20 ms push exciting a 20-80 Hz rumble
  kStray,  // a stray sound between bounces: a 30 ms band-limited (0.3-2.5 kHz) noise burst
};
std::string_view ToString(SoundEventKind kind);

struct ExtraEvent {
  SoundEventKind kind = SoundEventKind::kKnock;  // kKnock, kThump or kStray
  double onset_s = 0.1;
  double peak_amplitude = 0.2;  // approximate peak in full-scale units
};

// One output channel (microphone). Channel c hears every source event delay_s later, gain_db
// louder, with its own noise realisation at SNR noise.snr_db + snr_offset_db (measured on its
// own signal) and its own reverb tail.
struct ChannelOptions {
  double delay_s = 0.0;
  double gain_db = 0.0;
  double snr_offset_db = 0.0;
};

// The converter between the air and the file. A sigma-delta ADC (and a sample-rate converter)
// samples far above the output rate and decimates through a sharp FIR anti-aliasing filter; that
// filter, not the microphone, sets how a click's energy is spread in time. Linear-phase filters
// (the usual choice) ring symmetrically, so a click's energy appears a few samples BEFORE contact;
// minimum-phase ("low latency", "short delay") filters are causal and ring only after it.
enum class AdcFilterPhase {
  kLinear,   // zero-phase: its group delay is compensated, so file times stay contact times
  kMinimum,  // the causal filter with the same magnitude response (homomorphic design)
};
std::string_view ToString(AdcFilterPhase phase);

// SynthesisOptions::chain: the acoustic signal (modes, echoes, reverb, extra events, contact
// clicks) is rendered at oversampling x sample_rate_hz (the closed-form rendering is exact at any
// rate, and modes up to 0.45 x that rate are kept, since the filter removes them) and decimated
// by a Kaiser-windowed FIR low-pass (Kaiser 1974; Oppenheim & Schafer, "Discrete-Time Signal
// Processing", 7.5-7.6) whose band edges are fractions of sample_rate_hz. Noise, hum, DC offset,
// clipping and band_limit_hz are applied after it, at the output rate, as without a chain: they
// stand for the converter's own noise floor, mains pickup in the cabling, and the saturation of
// the output word (an analogue overload before the converter would instead be band-limited by
// the filter and overshoot). peak_amplitude then means the sampled peak of what reaches the
// file, and the SNR's signal power is the direct sound as recorded (filter and click included).
// How early the energy appears (docs/synthesis.md, bench/chain_lead_bench): at 16 kHz, where
// the filter cuts into the plate's modes, 1 % of an impact's peak is reached 0.3-0.5 ms before
// contact; at 44.1-48 kHz only a 35 us click's ringing shows, 20-40 us before contact.
// The defaults are those of audio converter data sheets:
//  - band edges 0.4535 / 0.5465 fs: Cirrus Logic CS8421 sample-rate converter (DS641: passband
//    0.4535 Fso, ripple +-0.007 dB, stop band from 0.5465 Fso, 125 dB) and the AKM "sharp
//    roll-off" filters (AK4385, AK4436: PB 0.4535 fs, SB 0.546 fs);
//  - 100 dB stop band: between the sigma-delta ADCs' 95 dB (Cirrus CS5381, DS563: passband
//    0.47 Fs, stop band from 0.58 Fs, group delay 12/Fs) and the converters' 125 dB; TI's
//    PCM1820/PCM1840 ADCs give 74-98 dB (passband 0.454 fs +-0.05 dB, 17.1/fs group delay);
//  - a stop band from 0.5 fs instead (stopband_edge_fraction = 0.5) is the alias-free choice of
//    software resamplers.
// The filter's figures are listed in SynthesizedRecording::chain.
struct RecordingChain {
  AdcFilterPhase phase = AdcFilterPhase::kLinear;
  // 2 to 64, or 0: automatic, the smallest factor >= 8 that renders at >= 384 kHz (8 at 48 and
  // 96 kHz, 9 at 44.1 kHz, 24 at 16 kHz). The filter's length in output samples does not depend
  // on it (the band edges set it), but the contact click is sampled at the high rate before
  // filtering, and its spectrum near that rate aliases: at 384 kHz the aliases stay 50 dB (35 us
  // contact) and 59 dB (70 us) under the filtered click's peak; 8 x 16 kHz gives only 36-45 dB.
  // 1 is refused: with nothing to decimate there is no anti-aliasing filter to model (use
  // band_limit_hz for a filter at the output rate).
  int oversampling = 0;
  double passband_edge_fraction = 0.4535;  // of sample_rate_hz; ripple below it is ~delta
  double stopband_edge_fraction = 0.5465;  // of sample_rate_hz, > passband, <= 1 - passband
  double stopband_attenuation_db = 100.0;  // 40 to 150 dB (delta = 10^(-dB/20) in both bands)
};

struct SynthesisOptions {
  int sample_rate_hz = 48000;  // 8 kHz to 384 kHz
  // Length of the file; 0 = up to the last event plus tail_s. Events at or after duration_s
  // are left out of the file and of the truth.
  double duration_s = 0.0;
  double tail_s = 1.0;
  double gravity_mps2 = 9.81;

  // Impacts: explicit ones when non-empty, otherwise the ballistic drop(s).
  std::vector<ImpactSpec> impacts;
  DropSpec drop;

  // The contact pulse: duration at reference_speed_mps, scaled as (v / v_ref)^
  // contact_duration_speed_exponent (-1/5 for a Hertz contact, 0 for a linear spring). Steel on
  // steel ~50-70 us, a ping-pong ball ~1 ms.
  double contact_duration_s = 70e-6;
  double contact_duration_speed_exponent = -0.2;
  // Amplitude: an impact at reference_speed_mps peaks at peak_amplitude (full scale, sampled
  // peak of its direct sound); other speeds scale as (v / v_ref)^amplitude_speed_exponent.
  // Exponent 1: the impulse m (1 + e) v grows linearly with speed, and modes much slower than
  // the contact respond to the impulse (faster impacts also get shorter, brighter pulses).
  double reference_speed_mps = 1.98;  // a 0.20 m drop
  double peak_amplitude = 0.5;
  double amplitude_speed_exponent = 1.0;
  // Standard deviation of a random per-impact level change (contact point, spin): real loudness
  // is not monotonic (alessia rimbalzi k = 4 is 2-4 dB louder than k = 1..3). 0 = off.
  double level_jitter_db = 0.0;
  std::vector<PlateMode> modes = SteelPlateModes();

  std::optional<ReverbOptions> reverb;
  std::optional<PrecursorOptions> precursor;
  std::optional<NoiseOptions> noise;
  std::optional<HumOptions> hum;
  std::vector<ExtraEvent> extra_events;
  double dc_offset = 0.0;  // added to every sample, full-scale units
  std::optional<LimiterOptions> limiter;
  std::optional<double> clip_level;  // hard clip at +-clip_level (0 < level <= 1) when set
  // Band limit of a lossy codec or phone path (the last step before the digital silence): a
  // zero-phase low-pass with a 10 % transition band, -74 dB above it. Like real codecs it rings
  // on both sides of a sharp onset, so the signal is then no longer exactly zero before it.
  std::optional<double> band_limit_hz;
  double leading_digital_silence_s = 0.0;  // exact zeros (no noise, hum or DC) at the start

  // Acceleration noise (Akay 1978, "A review of impact noise", JASA 64(4) 977; Richards,
  // Westcott & Jeyapalan 1979, "On the prediction of impact noise, I: Acceleration noise",
  // J. Sound Vib. 62(4) 547): the ball's sudden deceleration radiates a pressure pulse of its
  // own, before the plate has started to ring. Its time history follows the deceleration, i.e.
  // the contact force, so each ball impact adds a half-sine of its contact duration peaking at
  // click_gain x its peak_amplitude, with the impact's echoes and channel delay; precursors have
  // none. Positive is a compression (the side of the ball the deceleration points to, i.e. a
  // microphone above it); the plate modes' sign is not physical, so a negative gain is as
  // plausible a recording. This is the near-field term of the decelerating sphere's dipole
  // (Koss 1974, "Transient sound from colliding spheres", J. Sound Vib. 36(4) 541); beyond
  // c tau (1-2 cm for 35-70 us) the far-field term, the pulse's time derivative, dominates and
  // makes the real pulse bipolar with more energy near the band edge (so it would ring more
  // through a linear-phase chain); both start at contact. 0 = off. Without a chain the
  // half-sine is sampled as it is at the output rate: a 35-70 us pulse is not band-limited at
  // audio rates, so it ALIASES (its sampled peak depends on where the contact falls between
  // samples); give a chain for a recording whose click went through a real converter.
  double click_gain = 0.0;
  std::optional<RecordingChain> chain;  // unset: modes rendered at the output rate, no filter

  std::vector<ChannelOptions> channels = {ChannelOptions{}};
  std::uint64_t seed = 1;
};

// One event of the ground truth. For channel c the sound arrives at onset_s +
// channels[c].delay_s.
struct SynthesizedEvent {
  double onset_s = 0.0;
  SoundEventKind kind = SoundEventKind::kBallImpact;
  double impact_speed_mps = 0.0;  // ball impacts (and their precursors); 0 otherwise
  int drop_index = -1;            // 0-based drop of a ball impact/precursor; -1 otherwise
  // Peak of the event's direct sound at 0 dB channel gain (full scale): for ball impacts
  // peak_amplitude (v / v_ref)^amplitude_speed_exponent times the level jitter (the sampled peak
  // exactly for a speed-independent contact duration, within a few % otherwise).
  double peak_amplitude = 0.0;
};

// The anti-aliasing filter a chain used, as designed and measured (on a dense frequency grid of
// its taps).
struct RecordingChainSummary {
  RecordingChain chain;                  // as used: oversampling resolved when it was automatic
  int taps = 0;                          // at oversampling x sample_rate_hz
  double high_rate_hz = 0.0;             // oversampling x sample_rate_hz
  double kaiser_beta = 0.0;              // of the linear-phase design
  double passband_ripple_db = 0.0;       // largest |gain| in dB from 0 to the passband edge
  double stopband_attenuation_db = 0.0;  // smallest attenuation from the stopband edge up
  // Linear phase: the group delay, (taps - 1) / 2 high-rate samples, compensated (so energy
  // reaches this far BEFORE an onset). Minimum phase: 0 (nothing before an onset).
  double pre_ring_span_s = 0.0;
};

struct SynthesizedRecording {
  std::vector<Recording> channels;             // equal lengths, source_path empty
  std::vector<SynthesizedEvent> events;        // every event, sorted by onset_s
  std::vector<double> noise_rms;               // per channel; 0 without noise
  std::vector<int> clipped_sample_count;       // per channel
  std::vector<double> channel_delay_s;         // per channel: it hears an event at onset_s + this
  std::optional<RecordingChainSummary> chain;  // set when SynthesisOptions::chain was
  double click_gain = 0.0;                     // SynthesisOptions::click_gain

  // Onsets of the ball impacts only, sorted; optionally of one drop.
  std::vector<double> BallImpactOnsetsS(std::optional<int> drop_index = std::nullopt) const;
};

// Throws ConfigError (one line naming the option, its value and valid range) for an invalid
// option. SynthesizeBounces calls it first.
void ValidateSynthesisOptions(const SynthesisOptions& options);

// The ball impacts the options describe (explicit or ballistic), before rendering.
std::vector<SynthesizedEvent> PlanBallImpacts(const SynthesisOptions& options);

// Renders the recording. Deterministic for a given options.seed.
SynthesizedRecording SynthesizeBounces(const SynthesisOptions& options);

// CSV of the truth: header "onset_s,impact_speed_mps,kind,drop,peak_amplitude" and one line per
// event, times with 9 decimals (ns). With a recording chain or a contact click, '#' comment
// lines before the header describe them (readers of impact CSVs skip such lines); without, the
// text is exactly as before they existed.
std::string TruthCsv(const SynthesizedRecording& recording);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SYNTHESIZE_H_
