#ifndef BOUNCECAL_AUDIO_BOUNCE_SEQUENCES_H_
#define BOUNCECAL_AUDIO_BOUNCE_SEQUENCES_H_

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// What makes a run of impacts a bouncing ball. A ball that leaves impact k with restitution
// e_k flies dt_k = e_k dt_{k-1} (docs/physics.md section 1), so the interval ratio r_k = dt_k /
// dt_{k-1} is e_k: inside (0, 1), and changing only slowly from impact to impact (e depends on
// impact speed, ub-mth337 ping-pong goes 0.907 -> 0.95 over 60 bounces).
struct SequenceOptions {
  // Longest flight that still belongs to one drop: 3 s is a 11 m bounce.
  double max_interval_s = 3.0;
  // Accepted interval ratios. Above 1 only by timing noise (a ratio of 1.02 at the late,
  // short intervals is 0.4 ms of error on 20 ms), and the lowest e of a ball worth calibrating.
  double min_ratio = 0.2;
  double max_ratio = 1.02;
  // How far r may lie from the mean of the chain's last three ratios, on top of the change the
  // onset uncertainties allow (3 sigma).
  double ratio_step_tolerance = 0.12;
  // Flights shorter than this are chatter: a sequence stops there and says so. The detector's
  // default min_gap_ms: two rises closer than that are merged into one event, so shorter
  // flights cannot be told apart, while longer ones are heard as separate bounces and time e
  // to a few 0.1 % (a lively ball's audible bounces go on to 13-20 ms flights: the detector
  // suite's steel anvil at e = 0.95, a ping-pong ball on a table). It was 20 ms, where the
  // real recordings' sources see the ball chatter; there the sequence now ends where no bounce
  // is found.
  double chatter_interval_ms = 12.0;
  // Fewest impacts that form a sequence. Three give one ratio, which any three random sounds
  // with shrinking gaps also give; four give two ratios that must agree, which handling noise
  // and speech rarely do.
  int min_impacts = 4;
  // A chain with fewer than min_impacts impacts that rose in a band (the rest found only by the
  // ringing residual: late bounces in a ringing plate's or a room's tail) is still a sequence
  // when its timing could hardly be chance: each impact after the third lands this close to
  // where the previous interval ratio puts it, against the file's own rate of such events.
  // This is the probability, over all the chains the search tries in the file, that random
  // events line up as well (see FindBounceSequences).
  double max_chance_alignment = 1e-2;
  // The frame of the lossy transform codec the recording went through (CodecTiming::frame_s;
  // AnalyzeBounces sets it from the file). The codec draws its quantisation noise anew every
  // frame, and through an impact's ringing tail the ringing residual can rise at each: alessia
  // rimbalzi as AAC at 64 kbit/s per channel had 347 impacts (the WAV 46), ~300 residual-only,
  // 19-27 ms apart through the tails (the frame is 23.2 ms), 24-29 per s averaged over the file.
  // A chain through them beside the real bounces (36 impacts, 27 residual-only, 6 of the WAV's
  // bounces among the rest) passed the chance test at 3e-4 at that average; its predictions land
  // in the tails, where the events come once a frame (43 per s): 0.035-0.04 there, and the real
  // sequence is found. So the chance test counts residual-only events at the rate the chain's
  // own span shows (its count's upper end, ChanceAlignment::WeakRateOverTheSpan) up to one per
  // frame: where the codec made few such events (the detector suite's reverb_strong as Opus 64k,
  // 3 beside its drop over 0.7 s) one per frame refused the right chain (docs/codecs.md).
  std::optional<double> codec_frame_s;
  // Impacts (and tentative impacts) at or after this time (s) are never taken for bounces. A
  // lossy transform codec's stream ends in a frame the encoder padded after the cut that ended the
  // recording, and the decoder's output runs on to that frame's end: the cut, noise or ringing
  // stopped dead, is a step that the codec spreads over the frame before it as a burst of its own.
  // AnalyzeBounces sets this to two codec frames before the decoded end. Why: a sweep file (seed
  // 919 #105, a dead ball's 4 bounces in a 0.5 s room as AAC 96k) had a band-detected sound at
  // the cut, 8.6 ms before the decoded end, 20 dB over the noise above 6 kHz; it joined the first
  // bounce and 8 sounds of the codec's ~128 ms apart in the reverb into a chain that passed the
  // chance test (eta-bar 0.12 +- 0.06 against the ball's 0.89, exit 0). Without the cut's sound
  // the file forms no sequence. In the sweep's files 33 of 255 lossy ones hold a sound within 10
  // ms of their decoded end (15 of 1255 WAVs, which end at the cut and are left alone).
  std::optional<double> stream_end_transient_from_s;
  // The flight that would have preceded the first impact, 2 sqrt(2 h0 / g), when the drop
  // height h0 is known (--drop-height-m). It gives the first impact's restitution dt_1 / dt_0, so
  // a lossy ball (e ~ 0.3: lead, clay, wood on sand) that makes only 2 or 3 audible impacts still
  // forms a sequence (see BounceSequence::short_sequence); without it, 3 impacts give one ratio.
  std::optional<double> release_flight_s;

  // Throws ConfigError naming the option and its valid range.
  void Validate() const;
};

struct BounceSequence {
  std::vector<int> impact_indices;  // into the impact list, in time order
  std::string end_reason;           // why the sequence stops where it does
  // Fewer than min_impacts impacts: 2 or 3 band-detected impacts that are the loudest sounds
  // left in the file and whose interval ratios (with release_flight_s, the first against the
  // drop) are restitutions. Two or three sounds can time like that by chance, so such a
  // sequence is weak evidence and says so wherever it is reported.
  bool short_sequence = false;
  // The expected number of chains, among those the search tried in the file, that random events
  // would line up as well as this one (FindBounceSequences), where the chain needed the chance
  // test (fewer than min_impacts band-detected impacts, or passing over a louder sound); NaN
  // where it did not.
  double chance_alignment = std::numeric_limits<double>::quiet_NaN();
};

struct RejectedEvent {
  double time_s = 0;
  std::optional<int> impact_index;  // set when the event is in the impact list
  std::string reason;
};

// A sound that repeats at a fixed period among the impacts: mains hum heard as impacts, a motor,
// a ticking clock. Chains whose flights lie on multiples of its period are not sequences.
struct PeriodicEvents {
  double period_s = 0;
  int impacts_on_lattice = 0;  // impacts with another one or two periods away
};

struct SequenceResult {
  std::vector<BounceSequence> sequences;  // in time order
  // Every impact that is in no sequence, with the reason; sorted by time.
  std::vector<RejectedEvent> rejected;
  // For every impact, the 0-based sequence it belongs to.
  std::vector<std::optional<int>> sequence_of_impact;
  std::optional<PeriodicEvents> periodic_events;
};

// Groups impacts into bounce sequences: repeatedly takes the longest chain of unassigned
// impacts whose interval ratios behave like a bouncing ball (each next impact is searched in
// the window the mean of the last three ratios predicts, the loudest one there is taken), then
// rejects what lies inside it (stray sounds), before it (knocks, handling) and after it (chatter,
// rolling, noise), each with a reason. A chain counts when its first min_impacts impacts rose in
// a band, or when it starts with two that did and its timing passes max_chance_alignment, or,
// where no band-detected second impact makes a chain from a first that rose, with a second only
// the ringing residual found and its timing passes a hundredth of max_chance_alignment (a chain
// family of its own, counted apart):
// impact k >= 4 lands |t_k - t_pred| from t_pred = t_{k-1} + r dt_{k-1} (r that mean), which a
// random event of its kind (band or residual-only, at the rate of the file's events of that kind
// the chain has not taken before impact k) beats with probability
// p_k = 1 - exp(-2 rate |t_k - t_pred|) whatever its timing precision. Two
// statistics combine them: Fisher's -sum ln p_k (a Gamma(m, 1) tail for random events), and
// q = sum (|t_k - t_pred| / w_k)^2 with w_k the flight scaled for the ratio's prediction error,
// which a ball whose e scatters keeps small whatever the scatter (its chance for random events is
// bounded by prod(2 rate w_k) times the volume of the m-ball of radius sqrt(q) over 2^m). Twice the
// smaller chance (one chance alone for m = 1), times the number of chains tried (pairs of
// band-detected impacts times the third impacts the first ratio's window offers), must stay below
// max_chance_alignment (the residual-only-second family: pairs of a band-detected first and a
// residual-only second). A chain that fails may drop residual-only members from its end while
// min_impacts are left, its chance multiplied by the versions tried. A chain the test judges,
// and every chain accepted, must also shrink its flights as a ball does: its last flight shorter
// than its first by 3 sigmas of the four onsets' stated timing, and time its ratios as one ball
// can: a line in the bounce number (e drifts with impact speed) with a scatter of 5 % from impact
// to impact on top of the stated timing, beyond which random shrinking gaps lie with chance
// below 1e-6 (sequences/ratio_scatter.h). Where the file's events repeat at
// one period (mains hum heard as impacts, a motor, a clock: periodic_events), a chain whose
// flights lie on its multiples more often than random flights would with probability 1e-3 is no
// sequence, whatever its test. Deterministic. Throws ConfigError for bad options.
SequenceResult FindBounceSequences(const std::vector<Impact>& impacts,
                                   const SequenceOptions& options = {});

// The bounce sequence as a prior for the quiet end of a drop: extends every sequence found in
// `impacts` at its end with impacts from `tentative` (rises too weak to count on their own)
// that fall where the next bounce is due, t_n + r dt_n with r the last interval ratio, within
// half the usual ratio_step_tolerance, while no impact of `impacts` lies in that window and
// flights stay above chatter_interval_ms. After an adoption, a window holding exactly one impact
// of `impacts` that no sequence took is passed through (that impact is the bounce due there,
// which the sequence could not reach before) and adoption goes on after it. A chain that the
// chance test refused is extended the same way where it then passes that test at
// max_chance_alignment, every tentative impact counted as an event of its own kind at its own
// rate and each shorter extension tried counted against it. Returns `impacts` plus the adopted
// ones (flagged residual_only), in time order. Deterministic. Throws ConfigError for bad options.
std::vector<Impact> ExtendSequencesWithTentative(const std::vector<Impact>& impacts,
                                                 const std::vector<Impact>& tentative,
                                                 const SequenceOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_BOUNCE_SEQUENCES_H_
