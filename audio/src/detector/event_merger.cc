#include "detector/event_merger.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bouncecal::audio {

EventMerger::EventMerger(const DetectorOptions& options, double residual_hop_s, int sample_rate_hz,
                         const BandEnvelopes& bands)
    : rise_threshold_db_(options.rise_threshold_db),
      min_gap_ms_(options.min_gap_ms),
      residual_hop_s_(residual_hop_s),
      rate_hz_(sample_rate_hz),
      bands_(bands) {}

double EventMerger::OwnLevelDb(std::size_t band, double from, double to) const {
  const SampleHistory<float>& samples = bands_.band(band).samples;
  const std::int64_t begin =
      std::max<std::int64_t>(samples.begin(), std::llround(std::floor(from)));
  const std::int64_t end = std::min<std::int64_t>(samples.end(), std::llround(std::ceil(to)));
  double largest = 0;
  for (std::int64_t i = begin; i < end; ++i) {
    largest = std::max(largest, double{samples[i]} * samples[i]);
  }
  return EnvelopeDb(largest);
}

std::string EventMerger::BandName(std::size_t band) const {
  char text[48];
  std::snprintf(text, sizeof text, "the band above %.0f Hz", bands_.low_hz(band));
  return text;
}

void EventMerger::Add(const LocatedImpact& next) {
  if (group_ && next.impact.onset_s - group_->kept.impact.onset_s < min_gap_ms_ * 1e-3) {
    Group& group = *group_;
    const LocatedImpact& kept = group.kept;
    group.rise_db = std::max(group.rise_db, next.rise_db);
    group.band_rise_db = std::max(group.band_rise_db, next.band_rise_db);
    // Each member's own sound, in the band where the pair rose most. The later one's span ends
    // where its candidate's examined frames end: no later sample is known to have been filtered
    // whatever the block sizes.
    const std::size_t band = next.band_rise_db > kept.band_rise_db ? next.band : kept.band;
    const double span =
        std::min({next.onset_sample - kept.onset_sample, kMaxOwnLevelMs * 1e-3 * rate_hz_,
                  static_cast<double>(next.span_end_sample) - next.onset_sample});
    const double kept_db = OwnLevelDb(band, kept.onset_sample, kept.onset_sample + span);
    const double next_db = OwnLevelDb(band, next.onset_sample, next.onset_sample + span);
    // A rise that did not reach the full threshold in the bands a few ms after a hit sits in
    // that hit's tail, whose level it shares: it never takes the onset from a hit that rose by
    // the full threshold. (Counting rises of half the threshold as band rises here was measured
    // worse: alessia rimbalzi split into 3 sequences, rubberball lost 4 impacts.) Nor does the
    // rest of a sound whose candidate closed while it was still rising. But a sound louder than
    // the hit's own by the full threshold, over the same span from each onset, is in no tail of
    // it (a tail decays): the hit was a precursor whose ringing, inside the later sound's
    // lookback, kept its band rise under the threshold (bench/silent_wrong_sweep.py seed 3 #62,
    // a precursor 6.1 ms and 14 dB before each bounce: at the 4th, the bounce 13.6 dB louder in
    // the band above 6 kHz lost to it and was timed 6.2 ms early at a stated 73 us).
    const bool louder_by_a_rise = next_db - kept_db >= rise_threshold_db_;
    // Where neither rose by the full threshold, both sit in a tail whose level they share, and
    // their levels tell little: the later one keeps the onset only if the ringing residual rose
    // at least as much at it (a novelty not measured compares as equal). silent_wrong_sweep seed
    // 7 #54: an in-ringing sound 11 ms after the 5th bounce, 0.9 dB louder over 7.1 ms but with
    // a residual rise of 0.4 dB against the bounce's 5.5 dB, took its onset (+11.3 ms at a
    // stated 1.9 ms, eta-bar 3.7 sigmas off). Only while their levels are that close: the pairs
    // the rule decided in the sweep differed by 0.2-1.1 dB, whereas a sound louder by half the
    // rise threshold over the same span is a new hit, and a transform codec's pre-echo, new noise
    // all over the spectrum, can out-rise it in the residual (the detector suite's very_high_e as
    // AAC 64k at 16 kHz: its 5th bounce, 9.2 dB louder than the pre-echo 10.9 ms before it, lost
    // to it, and eta-bar read 0.1410 against the WAV's 0.1057 at 7.6 sigmas).
    const bool in_ringing = !next.band_rose && !kept.band_rose;
    const bool less_novel = next.impact.ringing_novelty_db < kept.impact.ringing_novelty_db;
    const bool close_in_level = next_db - kept_db < 0.5 * rise_threshold_db_;
    // Where both rose by the full threshold, a later sound less than half a threshold louder is
    // no new hit either: one impact whose sound builds up for milliseconds (a counter's or a
    // plate's modes, a codec's attack), split into two candidates where the tracker's frames
    // fell, is the louder over the same span from its later part whichever it is, and the start
    // of contact comes first. The detector suite's knock_speech_before as Opus 48k: a bounce
    // whose first candidate closed 2.9 ms in, the second 1.8 dB louder over 0.5 ms, was timed
    // 2.8 ms late at a stated 252 us (eta-bar 0.5616 against the WAV's 0.5507). A precursor click
    // is 9-14 dB under its bounce, and where one comes that close, the bounce stays recorded as
    // the merged sound for the sequence to weigh (merged_alternatives.h).
    const bool louder_alike =
        in_ringing ? next_db > kept_db && !(less_novel && close_in_level) : !close_in_level;
    const bool next_wins =
        !next.continuation &&
        (next.band_rose == kept.band_rose ? louder_alike : next.band_rose || louder_by_a_rise);
    Merge merge;
    merge.span_ms = span / rate_hz_ * 1e3;
    merge.band = band;
    if (next_wins) {
      merge.merged = kept;
      merge.winner = next;
      merge.precursor = true;
      merge.level_difference_db = next_db - kept_db;
      group.others.push_back(merge);
      group.kept = next;
    } else {
      merge.merged = next;
      merge.winner = kept;
      merge.level_difference_db = kept_db - next_db;
      merge.why =
          next.continuation                  ? "the rest of its sound"
          : next.band_rose != kept.band_rose ? "no band rose by the full threshold there"
          : !in_ringing && next_db > kept_db
              ? "louder by less than half the rise threshold: the impact's sound building up"
              : nullptr;
      group.others.push_back(merge);
    }
    return;
  }
  Emit();
  group_ = Group{next, next.rise_db, next.band_rise_db, {}};
}

void EventMerger::Flush() { Emit(); }

// A sound that rose less in the tail than this many rise thresholds (band scale; a ringing
// novelty of 1 dB where 0.6 dB is the threshold) is located worse than one residual hop.
constexpr double kHopLocatingRises = 5.0 / 3.0;

double EventMerger::WeakOnsetSigmaS(const LocatedImpact& located) const {
  // Its onset is picked on a flank inside the tail that the residual located only to within its
  // frame hop, and the less the sound rose above what the ringing explains, the more the noise
  // and the ringing's own swings move that flank. Scored against the exact onsets of 3443
  // residual-only sequence members of the random-impairment sweep (bench/silent_wrong_sweep.py,
  // seeds 101/23/43 and --only-unreliable-lobe 3/5/7/11, 200 files each), with the hop as sigma:
  // those that rose by 1.67 thresholds or more were within 1.96 sigmas in 98.6 %, beyond 3 in
  // 0.3 %; those below, 93-95 % and 1.6-4.2 % (seed 11 #85: a 5th bounce under the noise, its
  // novelty 0.43 dB, 9.0 ms late at a stated 1.9 ms, eta-bar 4.6 sigmas off). The hop scaled by
  // the rise's shortfall (at most 3.3 times: a tentative rose by half the threshold at least)
  // covers those 97-98 % and 0.7-1.5 %, near the clearer ones; no onset moves.
  const double rise_db = std::max(located.rise_db, 0.5 * rise_threshold_db_);
  return residual_hop_s_ * std::max(1.0, kHopLocatingRises * rise_threshold_db_ / rise_db);
}

void EventMerger::Emit() {
  if (!group_) return;
  LocatedImpact& kept = group_->kept;
  Impact& impact = kept.impact;
  if (group_->rise_db >= rise_threshold_db_) {
    if (group_->band_rise_db < rise_threshold_db_) impact.residual_only = true;
    if (impact.residual_only) {
      // Its onset is picked on a flank inside the tail that the residual located only to within
      // its frame hop: on the synthetic free plate, in rooms and under level jitter such onsets
      // were off by a median of 133 us, p90 1.5 ms, up to 8 ms, while the picker claimed ~50 us
      // (42 % within 2 sigma). Stated as at least one hop, like the tentative ones below, so the
      // e and eta around it carry that.
      impact.onset_uncertainty_s = std::max(impact.onset_uncertainty_s, WeakOnsetSigmaS(kept));
    }
    impacts_.push_back(kept);
    for (auto& other : group_->others) merged_.push_back(std::move(other));
  } else if (kept.change_point_found) {
    // Rose by at least half the threshold: not an impact on its own, but it may continue a
    // bounce sequence where the next bounce is due (ExtendSequencesWithTentative). Such a weak
    // onset is picked on a flank the residual located only to within its frame hop; on the
    // free-plate ground truth adopted onsets were 1-1.5 ms off while the picker claimed tens of
    // us, so the stated uncertainty is at least one hop.
    // Every group member passed the onset locator's SNR gate, in its band or only against the
    // noise under the ringing, as an impact may. Requiring the band's own SNR as well lost the
    // quiet end of a lively ball's drop: its bounces every 20-30 ms keep every band ringing, so
    // the bands' minimum-statistics floors are that ringing (a synthetic ping-pong drop's bounce
    // 25, 12 dB over the 3.5 ms before it in the 1-4 kHz band, stood 6.9 dB over the 2 kHz
    // band's floor and was dropped, and the sequence ended there). But a rise whose change point
    // did not stand out of its search's start has no onset to adopt: such picks sat near that
    // start, 2.4-7.4 ms from the impact (the detector suite: 6 of the 7 in-ringing picks so
    // placed; noise_snr12's bounce 7, 2.6 ms early, was adopted as a false alarm when every
    // gated rise was kept), and adopted ones were off by 1-2 ms (bench/detector_accuracy_bench:
    // extra detections 107 -> 113 with them, 106 without).
    impact.residual_only = true;
    impact.onset_uncertainty_s = std::max(impact.onset_uncertainty_s, WeakOnsetSigmaS(kept));
    tentative_.push_back(kept);
  }
  group_.reset();
}

double EventMerger::Onset(const LocatedImpact& located, double reference_to_contact_s) {
  return located.impact.onset_s - (located.by_reference ? reference_to_contact_s : 0.0);
}

void EventMerger::Report(double reference_to_contact_s, DetectionResult& result) const {
  for (const LocatedImpact& located : impacts_) {
    result.impacts.push_back(located.impact);
    result.impacts.back().onset_s = Onset(located, reference_to_contact_s);
  }
  for (const LocatedImpact& located : tentative_) {
    result.tentative.push_back(located.impact);
    result.tentative.back().onset_s = Onset(located, reference_to_contact_s);
  }
  for (const Merge& merge : merged_) {
    const double merged_s = Onset(merge.merged, reference_to_contact_s);
    const double winner_s = Onset(merge.winner, reference_to_contact_s);
    const double gap_ms = std::fabs(winner_s - merged_s) * 1e3;
    const std::string where = BandName(merge.band);
    char text[256];
    if (merge.precursor) {
      std::snprintf(text, sizeof text,
                    "precursor %.1f ms before the impact at %.5f s, whose first %.1f ms are "
                    "%.1f dB louder in %s (merged; min gap %.3g ms)",
                    gap_ms, winner_s, merge.span_ms, merge.level_difference_db, where.c_str(),
                    min_gap_ms_);
    } else if (merge.why) {
      std::snprintf(text, sizeof text,
                    "echo or secondary burst %.1f ms after the impact at %.5f s (%s; merged; "
                    "min gap %.3g ms)",
                    gap_ms, winner_s, merge.why, min_gap_ms_);
    } else {
      std::snprintf(text, sizeof text,
                    "echo or secondary burst %.1f ms after the impact at %.5f s, %.1f dB "
                    "quieter over its first %.1f ms in %s (merged; min gap %.3g ms)",
                    gap_ms, winner_s, merge.level_difference_db, merge.span_ms, where.c_str(),
                    min_gap_ms_);
    }
    result.merged.push_back({merged_s, merge.merged.impact.peak_dbfs, text, winner_s,
                             !merge.precursor && merge.merged.continuation,
                             merge.level_difference_db});
  }
}

}  // namespace bouncecal::audio
