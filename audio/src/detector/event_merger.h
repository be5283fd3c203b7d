#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_EVENT_MERGER_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_EVENT_MERGER_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "detector/band_envelopes.h"
#include "detector/onset_locator.h"

namespace bouncecal::audio {

// Stage 5 of the impact detector: one sound, one impact. Located candidates closer than
// min_gap_ms to the one kept so far are one event (a precursor before a hit, an echo or a
// secondary burst after it): one of them is the impact, the others are listed as merged with
// the reason. Members only need half the threshold, so a main burst that rises a few dB over its
// own precursor still takes the onset; the group counts as an impact when one member rose by
// the full rise_threshold_db. A group that rose by half the threshold only is kept as a
// tentative impact (see DetectionResult::tentative).
//
// Which member is the impact is decided by evidence each one carries by itself: the loudest
// sample of the sound its own onset starts, in the band where the pair rose most, over as long
// after each onset as the two are apart (at most kMaxOwnLevelMs): the earlier one's never
// reaches the later onset. A rise that fires a few ms early (ringing of earlier impacts that
// beats, a room's build-up, noise) starts only what was already there, while the real impact's
// onset starts the energy; measuring both over the candidate's whole span instead gave the
// early one the impact's loudness and kept it. The span is the gap rather than a fixed short
// window because a soft contact (rubber, tennis) takes several ms to reach its peak, and a
// precursor or echo within that time would otherwise be compared with its rising edge only.
class EventMerger {
 public:
  // residual_hop_s: the ringing residual's frame hop, the least uncertainty of an onset that
  // only the residual located. The bands' histories must hold the samples from the kept
  // member's onset on when the next one arrives (min_gap_ms plus a candidate's span).
  EventMerger(const DetectorOptions& options, double residual_hop_s, int sample_rate_hz,
              const BandEnvelopes& bands);

  void Add(const LocatedImpact& next);
  // Emits the group still open; call at the end of the stream.
  void Flush();

  const std::vector<LocatedImpact>& impacts() const { return impacts_; }
  // The impacts, merged events and tentative impacts as the detector reports them: every
  // onset that is a timing reference moved back by reference_to_contact_s (see
  // ReferenceToContactOffset), the same in the merge reasons.
  void Report(double reference_to_contact_s, DetectionResult& result) const;

  // The longest span after an onset over which its own level is measured.
  static constexpr double kMaxOwnLevelMs = 12.0;

 private:
  // A member that was not kept, with what the reason says about it.
  struct Merge {
    LocatedImpact merged;
    LocatedImpact winner;            // the member it lost to
    bool precursor = false;          // before the winner (else an echo or secondary burst after it)
    double level_difference_db = 0;  // winner minus merged, over span_ms each from its onset
    double span_ms = 0;
    std::size_t band = 0;
    const char* why = nullptr;  // a reason other than loudness, or nullptr
  };
  struct Group {
    LocatedImpact kept;
    double rise_db = 0;       // the largest of its members
    double band_rise_db = 0;  // the same, from the band rises alone
    std::vector<Merge> others;
  };
  void Emit();
  // The least uncertainty of an onset picked inside a tail (residual_only), from how clearly
  // its sound rose there (event_merger.cc).
  double WeakOnsetSigmaS(const LocatedImpact& located) const;
  static double Onset(const LocatedImpact& located, double reference_to_contact_s);
  // The largest squared sample of `band` in [from, to) (fractional sample indices), in dB;
  // -140 dB for an empty span or samples no longer held.
  double OwnLevelDb(std::size_t band, double from, double to) const;
  std::string BandName(std::size_t band) const;

  double rise_threshold_db_;
  double min_gap_ms_;
  double residual_hop_s_;
  int rate_hz_;
  const BandEnvelopes& bands_;
  std::optional<Group> group_;
  std::vector<LocatedImpact> impacts_;
  std::vector<Merge> merged_;
  std::vector<LocatedImpact> tentative_;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_EVENT_MERGER_H_
