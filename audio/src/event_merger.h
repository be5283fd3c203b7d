#ifndef BOUNCECAL_AUDIO_SRC_EVENT_MERGER_H_
#define BOUNCECAL_AUDIO_SRC_EVENT_MERGER_H_

#include <optional>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "onset_locator.h"

namespace bouncecal::audio {

// Stage 5 of the impact detector: one sound, one impact. Located candidates closer than
// min_gap_ms to the one kept so far are one event (a precursor before a hit, an echo or a
// secondary burst after it): one of them is the impact, the others are listed as merged with
// the reason. Members only need half the threshold, so a main burst that rises a few dB over its
// own precursor still takes the onset; the group counts as an impact when one member rose by
// the full rise_threshold_db. A group that rose by half the threshold only is kept as a
// tentative impact (see DetectionResult::tentative).
class EventMerger {
 public:
  // residual_hop_s: the ringing residual's frame hop, the least uncertainty of an onset that
  // only the residual located.
  EventMerger(const DetectorOptions& options, double residual_hop_s);

  void Add(const LocatedImpact& next);
  // Emits the group still open; call at the end of the stream.
  void Flush();

  std::vector<Impact>& impacts() { return impacts_; }
  std::vector<MergedEvent>& merged() { return merged_; }
  std::vector<Impact>& tentative() { return tentative_; }

 private:
  struct Group {
    LocatedImpact kept;
    double rise_db = 0;       // the largest of its members
    double band_rise_db = 0;  // the same, from the band rises alone
    std::vector<MergedEvent> others;
  };
  void Emit();

  double rise_threshold_db_;
  double min_snr_db_;
  double min_gap_ms_;
  double residual_hop_s_;
  std::optional<Group> group_;
  std::vector<Impact> impacts_;
  std::vector<MergedEvent> merged_;
  std::vector<Impact> tentative_;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_EVENT_MERGER_H_
