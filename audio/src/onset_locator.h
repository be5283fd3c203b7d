#ifndef BOUNCECAL_AUDIO_SRC_ONSET_LOCATOR_H_
#define BOUNCECAL_AUDIO_SRC_ONSET_LOCATOR_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "band_envelopes.h"
#include "bouncecal/audio/impact_detector.h"
#include "candidate_tracker.h"
#include "detector_frames.h"
#include "novelty_sources.h"
#include "sample_history.h"

namespace bouncecal::audio {

// A candidate with its onset located and its evidence measured: what the merger weighs.
struct LocatedImpact {
  Impact impact;
  double level_db = 0;      // band 0's peak over the candidate
  double rise_db = 0;       // the larger of its band rise and residual novelty (band scale)
  double band_rise_db = 0;  // its band rise alone
  // False when no band rose by the full threshold: its level is then mostly the tail it is in.
  bool band_rose = true;
  bool continuation = false;  // the rest of a sound whose candidate was closed while rising
};

// Stage 4 of the impact detector: where in a candidate the impact's contact began, and how
// clearly it stands out. The SNR gate (min_snr_db) is checked in the band that rose most, or,
// inside a tail, against the noise under the ringing. The onset is picked in that band with the
// AIC change point and leading-edge fit of onset_picker.h; where no band rose by the full
// threshold the impact sits in a tail louder than itself, and the onset is picked on the
// linear-prediction innovation of the band (prediction_innovation.h), where the tail is removed.
class OnsetLocator {
 public:
  // raw: the unfiltered samples, for the impact's peak level.
  OnsetLocator(const DetectorFrames& frames, const DetectorOptions& options, BandEnvelopes& bands,
               const RingingResidualNovelty& residual, const SampleHistory<float>& raw);

  // Nothing when the candidate fails the SNR gate.
  std::optional<LocatedImpact> Locate(const Candidate& candidate);

  // Samples the bands' histories must hold before the newest frame examined.
  static std::size_t HistorySamples(int sample_rate_hz);

 private:
  const DetectorFrames frames_;
  double rise_threshold_db_;
  double min_snr_db_;
  BandEnvelopes& bands_;
  const RingingResidualNovelty& residual_;
  const SampleHistory<float>& raw_;
  // The previous candidate's peak sample: a pick window never reaches back past it.
  std::int64_t last_peak_sample_ = -1;
  std::vector<float> window_;  // scratch
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_ONSET_LOCATOR_H_
