#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_CANDIDATE_TRACKER_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_CANDIDATE_TRACKER_H_

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

#include "detector/band_envelopes.h"
#include "detector/detector_frames.h"
#include "detector/novelty_sources.h"

namespace bouncecal::audio {

// A stretch of frames where new sound rose: what the onset locator examines.
struct Candidate {
  std::int64_t frame = 0;       // where its sound began: the first frame that rose
  std::int64_t opened_at = 0;   // the frame n whose rise opened it (frame <= n <= frame + attack)
  std::int64_t peak_frame = 0;  // band 0's loudest frame since
  double peak_db = 0;           // band 0's level there
  std::size_t band = 0;         // the band that rose most: the onset is picked there
  std::int64_t band_peak_frame = 0;  // that band's loudest frame since the candidate opened
  double rise_db = 0;                // the largest band rise
  double residual_rise_db = 0;       // the largest ringing-residual novelty, on the band scale
  // The same counted only over what a transform codec did not leave out (NoveltyRise::
  // codec_rise_db): the sound's own evidence where no band carried it.
  double residual_codec_rise_db = 0;
  // The largest rise of the low band (NoveltyRise::low_band_rise_db).
  double low_band_rise_db = -std::numeric_limits<double>::infinity();
  // Opened by the residual, re-armed a window after the last candidate without a fall or a dip
  // (CandidateTracker): its pick may find nothing but the rise that candidate had found.
  bool armed_past_window = false;
  // Opened right after a candidate that was closed while still rising: the rest of its sound.
  bool continues = false;
  // The first frame of a second, louder sound inside it: a full band rise that began more than
  // `attack` after the candidate's own sound had peaked, at least the full threshold above all of
  // it (a precursor and its impact, or a filter's pre-ringing and the click, kept as one); -1
  // where none. The onset locator widens the onset's uncertainty over the two.
  std::int64_t later_sound_frame = -1;
  std::int64_t closed_at = 0;           // the frame n that closed it
  std::ptrdiff_t closed_in_block = -1;  // its index in its block (-1: at the end of the stream)
  // Closed while the band that rose most was at its loudest so far (band 0 can have closed it,
  // held by a louder tail): its sound was still rising in that band, so its pick window ended
  // inside a rising edge, not at a peak (the onset locator lets the next candidate's pick window
  // reach back past that end where this one rose by the full threshold and its onset lies just
  // before it).
  bool closed_rising = false;
};

// Stage 3 of the impact detector: opens a candidate where a novelty source rises by half the
// threshold, keeps it open while band 0 keeps reaching new peaks (so a hit that builds up over
// several milliseconds, or grows out of its precursor, is one candidate), and closes it `peak`
// frames after its last peak, at most `max_open` frames after it opened.
class CandidateTracker {
 public:
  // residual_window_frames: the ringing residual's window in envelope frames, after which a
  // closed candidate in which no onset was found can no longer be the novelty's source (the
  // default never counts it so).
  CandidateTracker(const DetectorFrames& frames, const DetectorOptions& options,
                   const BandEnvelopes& bands,
                   std::int64_t residual_window_frames = std::numeric_limits<std::int64_t>::max());

  bool open() const { return open_; }
  // Band 0's level of frame n, for the peak of an open candidate (every frame, before Step).
  // The test inline and the tracking out of line, as for Step.
  void TrackPeak(std::int64_t n) {
    if (open_) TrackOpenPeak(n);
  }
  // Whether the band rise of this frame is needed even below the secondary threshold: inside a
  // candidate, and where the residual opens one (its band and rise come from the bands).
  bool WantsBandRise(const NoveltyRise& residual) const {
    return open_ || (residual_armed_ && residual.rise_db >= secondary_threshold_db_);
  }
  // Frame n (m = n - attack is the frame whose rises these are); returns the candidate it
  // closes, if any.
  // Most frames are outside candidates and rise by less than the secondary threshold in both
  // sources: those only re-arm the residual (as StepOpenOrRising would) inline, without a call
  // per frame.
  std::optional<Candidate> Step(std::int64_t n, std::ptrdiff_t k, const NoveltyRise& band,
                                const NoveltyRise& residual) {
    if (!open_ && band.rise_db < secondary_threshold_db_ &&
        residual.rise_db < secondary_threshold_db_) {
      if (residual.rise_db <= closed_residual_rise_db_ - secondary_threshold_db_) {
        residual_dipped_ = true;
      }
      residual_armed_ = true;
      armed_past_window_ = false;
      return std::nullopt;
    }
    return StepOpenOrRising(n, k, band, residual);
  }
  // The onset locator found no change point in the candidate Step closed last: its search looked
  // alike throughout (a codec's pre-echo or noise rising into what follows), so no sound of its
  // own began there that could still be growing in the residual (see residual_window_frames).
  void ClosedCandidateFoundNoOnset() { closed_found_no_onset_ = true; }
  // The candidate still open at the end of the stream, closed at frame `last`.
  std::optional<Candidate> Finish(std::int64_t last);

 private:
  std::optional<Candidate> StepOpenOrRising(std::int64_t n, std::ptrdiff_t k,
                                            const NoveltyRise& band, const NoveltyRise& residual);
  void TrackOpenPeak(std::int64_t n);
  // Where the sound whose rise frame n reports began: the first frame of the attack window that
  // rose by the secondary threshold over the reference.
  std::int64_t FirstRisingFrame(const NoveltyRise& band, std::int64_t n, std::ptrdiff_t k) const;
  // Records in the open candidate a second, louder sound whose rise frame n reports (see
  // Candidate::later_sound_frame).
  void NoteLaterSound(const NoveltyRise& band, std::int64_t n, std::ptrdiff_t k);

  const DetectorFrames frames_;
  double threshold_db_;
  double secondary_threshold_db_;
  double rising_ratio_;  // its power ratio, less PowerToDb's margin
  // The loudest frame of `band` in [from, to].
  std::int64_t LoudestFrame(std::size_t band, std::int64_t from, std::int64_t to) const;

  const BandEnvelopes& bands_;
  bool open_ = false;
  // A residual frame spans a few ms, so after a hit it stays above its pre-hit reference for
  // that long: the residual opens a candidate only after it has fallen back below the
  // threshold once (hysteresis), never on the lingering frames of the last candidate, or after
  // it dipped and then rose far above that candidate's (a new sound; see Step).
  bool residual_armed_ = true;
  // The largest residual rise of the last candidate closed (at least the secondary threshold),
  // and whether the residual has since dipped half the threshold under it (see Step).
  double closed_residual_rise_db_ = 0;
  bool residual_dipped_ = false;
  std::int64_t residual_window_frames_;
  bool transform_coded_;  // DetectorOptions::transform_coded
  // The first frame of the last candidate closed, and whether the locator found no onset in it.
  std::int64_t closed_frame_ = std::numeric_limits<std::int64_t>::min() / 2;
  bool closed_found_no_onset_ = false;
  // The residual was re-armed by the window after the last candidate, not by a fall or a dip.
  bool armed_past_window_ = false;
  std::int64_t still_rising_until_ = -1;
  Candidate candidate_;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_CANDIDATE_TRACKER_H_
