#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_LOCATOR_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_LOCATOR_H_

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "detector/band_envelopes.h"
#include "detector/candidate_tracker.h"
#include "detector/detector_frames.h"
#include "detector/novelty_sources.h"
#include "detector/sample_history.h"

namespace bouncecal::audio {

// A candidate with its onset located and its evidence measured: what the merger weighs.
struct LocatedImpact {
  Impact impact;
  std::size_t band = 0;              // where the onset was picked (the band that rose most)
  double onset_sample = 0;           // the onset, as a fractional sample index
  std::int64_t span_end_sample = 0;  // the end of the frames the candidate examined
  double rise_db = 0;       // the larger of its band rise and residual novelty (band scale)
  double band_rise_db = 0;  // its band rise alone
  // False when no band rose by the full threshold: its level is then mostly the tail it is in.
  bool band_rose = true;
  bool continuation = false;  // the rest of a sound whose candidate was closed while rising
  // False where the search's own first sample fits the window within two sigmas of the change
  // point (PickOnset's start_aic_excess): the change point did not find where the impact began
  // inside the search, the whole search looking alike (an impact too weak against the tail it
  // is in, or one that began before the search), and the onset sits near the search's start.
  bool change_point_found = true;
  // impact.onset_s is its timing reference (see ReferenceCrossing in onset_picker.h), which the
  // detector turns into the start of contact by one offset for the whole recording
  // (ReferenceToContactOffset); false where no reference could be placed and onset_s is the
  // start of contact itself.
  bool by_reference = false;
  // Reference minus start of contact, where both come from this impact's fitted edge; NaN
  // otherwise.
  double reference_lead_s = std::numeric_limits<double>::quiet_NaN();
};

// The offset from the timing reference to the start of contact for a whole recording: the
// median over its impacts of their own fitted reference_lead_s (0 without any). One offset for
// all impacts keeps their intervals those of the references, whose spread does not grow with
// loudness, while onsets stay starts of contact on average.
double ReferenceToContactOffset(const std::vector<LocatedImpact>& impacts);

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
  // How a candidate passed the SNR gate.
  struct SnrGate {
    double snr_db = 0;    // in the band that rose most, against that band's floor
    bool in_band = true;  // false: it passed only against the ringing residual's floor
  };
  // The stretch of one band's samples that the onset is picked in (held in window_): what was
  // there before the impact, then the impact's rising edge up to its largest sample.
  struct PickWindow {
    std::int64_t search_begin = 0;  // the earliest sample the onset may be at
    std::int64_t begin = 0;         // the sample index of window_[0]
    std::size_t search_offset = 0;  // search_begin as an index into window_
    std::int64_t peak = 0;          // the impact's largest sample: its edge ends there
    // window_ holds the prediction innovation (SwitchToInnovation) up to the candidate's end,
    // not just up to the peak.
    bool innovation = false;
  };

  // Nothing when the candidate fails the SNR gate.
  std::optional<SnrGate> CheckSnr(const Candidate& candidate) const;
  // The band the onset of a candidate that rose most in rising_band is picked in.
  std::size_t PickBand(std::size_t rising_band) const;
  // The earliest sample the onset is searched from, before clipping to what the band holds.
  std::int64_t SearchFrom(const Candidate& candidate, bool in_ringing) const;
  // Samples before the search that the window holds: noise for the picker, and in ringing
  // enough for the linear predictor's fit.
  std::int64_t SamplesBeforeSearch(bool in_ringing) const;
  // Fills window_ from samples and says where it lies.
  PickWindow FillPickWindow(const Candidate& candidate, const SampleHistory<float>& samples,
                            bool in_ringing);
  // In ringing: replaces window_ by its prediction innovation, where the tail is removed, and
  // ends the edge at the innovation's largest sample; leaves the window as it is when the
  // predictor could not be fitted.
  void SwitchToInnovation(PickWindow& window);
  // The largest raw level over kPeakLevelMs from the onset, in dBFS.
  double PeakDbfsAfter(double onset_index) const;

  const DetectorFrames frames_;
  double rise_threshold_db_;
  double min_snr_db_;
  BandEnvelopes& bands_;
  const RingingResidualNovelty& residual_;
  const SampleHistory<float>& raw_;
  // The previous candidate's peak sample: a candidate opened right after one closed while still
  // rising (Candidate::continues) whose search starts before it is the rest of that sound.
  std::int64_t last_peak_sample_ = -1;
  // A pick window never reaches back past this sample: the peak of the last candidate, unless
  // that one rose by the full threshold and closed while its band was still rising, with its
  // onset just before its peak.
  std::int64_t pick_floor_sample_ = -1;
  // The candidate that set pick_floor_sample_ closed while its band was still rising.
  bool pick_floor_rising_ = false;
  std::vector<float> window_;  // scratch
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_ONSET_LOCATOR_H_
