#ifndef BOUNCECAL_AUDIO_IMPACT_DETECTOR_H_
#define BOUNCECAL_AUDIO_IMPACT_DETECTOR_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bouncecal/audio/recording.h"

namespace bouncecal::audio {

// Knobs of the impact detector; the defaults are meant to work on recordings nobody tuned them
// for (see docs/recordings.md), so change them only with a reason.
struct DetectorOptions {
  // Pre-filter pass band. Below ~300 Hz sit DC, mains hum and handling/floor thumps; the
  // contact transient of a ball on a plate is broadband and its sharp leading edge lives in
  // the kHz range. band_high_hz <= 0 keeps everything up to the Nyquist frequency.
  double band_low_hz = 300.0;
  double band_high_hz = 0.0;
  // An impact is a frame whose energy rises at least rise_threshold_db above the loudest frame
  // of the preceding rise_lookback_ms (skipping the last 0.5 ms, where the rise itself starts).
  // Because the reference is what was there just before, a ringing tail raises the bar by
  // itself and no fixed level is needed; because it is the *loudest* recent frame, an echo or
  // a secondary burst within the lookback of a louder hit never rises above it.
  // The lookback must reach back from an echo (8-10 ms after a hit) to the hit's peak, and
  // bounces closer than it can only be told apart if the later one is louder. The first
  // lookback of a file is blind: with nothing before it, a rise cannot be measured.
  double rise_threshold_db = 10.0;
  double rise_lookback_ms = 12.0;
  // The impact's peak frame must also stand this far above the noise floor (minimum
  // statistics over ~2 s), which keeps quiet random fluctuations out.
  double min_snr_db = 12.0;
  // Two rises closer than this are one event: the louder one is kept (its onset is the impact),
  // the other is reported as a precursor or echo. 12 ms covers the 5-10 ms precursors and the
  // 8-10 ms echoes seen in real recordings; bounces that close are chatter anyway.
  double min_gap_ms = 12.0;
  // Also look for new energy that the decaying ringing of earlier impacts does not explain
  // (per-bin spectral novelty, src/ringing_residual.h): finds impacts buried in a long-ringing
  // plate's tail, where no band energy rises. Only consulted where a tail is present. It costs
  // about a quarter of the detection time (bench/analyze_bench), which turning it off saves on
  // recordings known to have no long ringing.
  bool ringing_residual = true;
  // Energy frame length of the envelope.
  double frame_ms = 0.25;
  // The samples were decoded from a transform codec (AAC, MP3, Vorbis, Opus), which leaves out
  // the bands a loud sound masks and codes them again as its bit allocation moves, and spreads an
  // attack's noise ahead of it: a sound that no band carried and that rose in the ringing residual
  // only in those bands is no impact (ringing_residual.h, CodecNoveltyDb), and the residual opens
  // a new candidate a window after the last one began without waiting for a dip
  // (candidate_tracker.cc). DetectImpactsInFile sets it from the file's codec.
  bool transform_coded = false;

  // Throws ConfigError naming the bad value and its valid range.
  void Validate(int sample_rate_hz) const;
};

struct Impact {
  double onset_s = 0;              // start of contact, sub-sample, from the first sample
  double onset_uncertainty_s = 0;  // one sigma
  double peak_dbfs = 0;            // peak |x| of the raw signal within 5 ms of the onset
  // How far the loudest detection band's envelope rose above its maximum over the lookback
  // before the onset (rise_lookback_ms), in dB; the envelope is floored at -140 dBFS, so an
  // impact out of digital silence reads up to about 140 dB.
  double rise_db = 0;
  // Where the ringing residual also rose: the mean over its frequency bins of each bin's rise
  // above its own maximum over the previous 20 ms, in dB (0.6 dB counts as a full
  // rise_threshold_db; src/ringing_residual.h). NaN where it was not consulted or did not rise.
  double ringing_novelty_db = std::numeric_limits<double>::quiet_NaN();
  double snr_db = 0;  // envelope peak above the noise floor
  // Weak evidence: no band energy rose by the full rise_threshold_db (the ringing residual's
  // novelty did), or it stood above the noise under the ringing but not above the band's own
  // floor, or it rose by only half the threshold and was adopted because it continues a bounce
  // sequence where the next bounce was due (ExtendSequencesWithTentative). That is how an impact
  // buried in the tail of earlier ones looks, and also how handling noise and speech can look,
  // so FindBounceSequences takes such an impact only where a bounce sequence predicts one, never
  // as its first (as its second only under a stricter chance test). Its onset is less precise
  // (up to ~1.5 ms off in tests).
  bool residual_only = false;
  // Its onset was measured from its whole response, aligned to the recording's template by its
  // waveform or its band envelopes, and is stated with that alignment's uncertainty
  // (response_timing.h): evidence of its own, which the merger's alternatives do not overrule
  // (merged_alternatives.h).
  bool timed_from_response = false;
  // Found only in the ringing, but its response aligned to the template's well enough to count
  // as band-detected (ResponseTimingOptions::confirming_correlation; residual_only is then
  // false). Its band rise is still missing, so a chain may need it as the weak second impact
  // that it was (FindBounceSequences).
  bool confirmed_by_response = false;
  // Where a louder sound begins within the impact's first milliseconds, its own first millisecond
  // 6 dB or more under that sound (detector/later_attack.h), s from the first sample; NaN where
  // none does. A click that rang into its bounce kept one candidate, whose onset is the click's,
  // and this is the bounce's: an alternative onset that a bounce sequence may take
  // (merged_alternatives.h).
  double later_onset_s = std::numeric_limits<double>::quiet_NaN();
  // With later_onset_s: how far that later sound's peak stands above the onset's own first
  // millisecond (dB).
  double later_sound_over_onset_db = std::numeric_limits<double>::quiet_NaN();
  // The sharpest rise of level from 2 ms after the onset to the next impact (detector/
  // later_attack.h, SharpestLaterRise): where it begins, s from the first sample, and its 0.5 ms
  // energy over that of the 2 ms before it (dB); NaN where the response was too short. A bounce
  // after a click that a limiter levelled with it shows here, not in later_onset_s.
  double later_rise_s = std::numeric_limits<double>::quiet_NaN();
  double later_rise_db = std::numeric_limits<double>::quiet_NaN();
  // Where the onset's search began before the last peak of an earlier candidate that closed while
  // still rising, so that the picker could not look before that peak: half the span from the
  // search's start to the onset, s (the sound that candidate rose into may be this one, begun
  // where the picker did not look); 0 otherwise. Not in onset_uncertainty_s, which the response
  // timing and the sequence tracking weigh (there it let a precursor drop's pairs switch sounds):
  // a bounce sequence states it for its members that the response timing did not time
  // (StateUnsearchedOnsetSpans, weak_member_doubt.h).
  double unsearched_span_s = 0;
  // One sigma of the flight that ends at this impact beyond the two onsets' own, s: where every
  // earlier member of its bounce sequence may sit on another sound together (a leading run timed
  // on its clicks, merged_alternatives.h), the run's shift moves this flight alone, and each
  // ratio inside the run keeps its value; where the members before it may be sounds before the
  // drop (a leading ratio off the later ones, leading_sounds.h), how far this flight is from the
  // one a bounce would have flown. 0 elsewhere.
  double incoming_flight_uncertainty_s = 0;
};

// A rise that was merged into a louder impact less than min_gap_ms away.
struct MergedEvent {
  double time_s = 0;
  double peak_dbfs = 0;
  std::string reason;
  // Onset of the member it lost to (where the response timing retimes that member, its new onset).
  double winner_s = 0;
  // Later than the winner and the rest of its sound (the winner's candidate closed while still
  // rising), so it kept the winner's onset whatever its level.
  bool rest_of_sound = false;
  // The winner's level minus this one's, each over the same span from its own onset (dB).
  double level_difference_db = 0;
};

struct DetectionResult {
  int sample_rate_hz = 0;
  std::int64_t samples = 0;
  std::vector<Impact> impacts;  // in time order
  std::vector<MergedEvent> merged;
  // Rises of only half rise_threshold_db that passed the SNR gate (flagged residual_only): not
  // impacts on their own, but a quiet late bounce in a tail looks like this, so GroupBounces
  // (bounce_analysis.h) adopts the ones that fall where a bounce sequence predicts the next
  // bounce.
  std::vector<Impact> tentative;
  // Median over impacts of snr_db (how clearly impacts stand out of this channel's noise); used
  // to pick the best channel. Minus infinity without impacts.
  double impact_to_noise_db = 0;
};

// Consecutive samples of a recording, from sample `begin` on.
struct SampleStretch {
  std::int64_t begin = 0;
  std::vector<float> samples;
};

// Streaming impact detector: feed samples of one channel in blocks of any size, then Finish().
// Memory is bounded (about 0.2 s of samples of history) whatever the length of the recording.
//
// A pipeline of stages, each in its own file under src/ (docs/detector.md draws the data flow):
// band envelopes (band_envelopes: causal FFT band-pass and high-passed sub-bands, energy frames,
// minimum-statistics noise floors) -> novelty sources (novelty_sources: band rise, ringing
// residual) -> candidate tracking (candidate_tracker) -> onset location (onset_locator: SNR gate,
// AIC change point and leading-edge fit of onset_picker, Maeda 1985, Sleeman & van Eck 1999;
// the linear-prediction innovation inside a tail) -> event merging of precursors and echoes
// (event_merger). Grouping into bounce sequences is the next stage (bounce_analysis.h).
class ImpactDetector {
 public:
  ImpactDetector(int sample_rate_hz, const DetectorOptions& options = {});
  ImpactDetector(const ImpactDetector&) = delete;
  ImpactDetector& operator=(const ImpactDetector&) = delete;
  ImpactDetector(ImpactDetector&&) noexcept;
  ImpactDetector& operator=(ImpactDetector&&) noexcept;
  ~ImpactDetector();

  // Keeps the samples from before_samples before to after_samples after every located impact
  // as the stream passes, for a stage that needs them after Finish (response_timing.h) without
  // a second pass over the recording. Call before the first Process.
  void KeepSamplesAroundImpacts(std::int64_t before_samples, std::int64_t after_samples);

  void Process(std::span<const float> samples);
  DetectionResult Finish();
  // The stretches kept (KeepSamplesAroundImpacts), in order, one where impacts' overlap; empty
  // if none were asked for.
  std::vector<SampleStretch> TakeKeptSamples();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Convenience: the whole recording at once.
DetectionResult DetectImpacts(const Recording& recording, const DetectorOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_IMPACT_DETECTOR_H_
