#include "candidate_tracker.h"

#include <algorithm>

namespace bouncecal::audio {
namespace {

// Rises of this fraction of rise_threshold_db open a candidate; it counts as an impact only if
// it or a member of its min-gap group reaches the full threshold (see EventMerger).
constexpr double kSecondaryRiseFraction = 0.5;

}  // namespace

CandidateTracker::CandidateTracker(const DetectorFrames& frames, const DetectorOptions& options,
                                   const BandEnvelopes& bands)
    : frames_(frames),
      secondary_threshold_db_(kSecondaryRiseFraction * options.rise_threshold_db),
      bands_(bands) {}

void CandidateTracker::TrackPeak(std::int64_t n) {
  if (!open_) return;
  const double level_db = bands_.band(0).Db(n);
  if (level_db > candidate_.peak_db) {
    candidate_.peak_db = level_db;
    candidate_.peak_frame = n;
  }
}

std::optional<Candidate> CandidateTracker::Step(std::int64_t n, std::ptrdiff_t k,
                                                const NoveltyRise& band,
                                                const NoveltyRise& residual) {
  if (residual.rise_db < secondary_threshold_db_) residual_armed_ = true;
  if (open_) {
    if (band.rise_db > candidate_.rise_db) {
      candidate_.rise_db = band.rise_db;
      candidate_.band = band.band;
    }
    candidate_.residual_rise_db = std::max(candidate_.residual_rise_db, residual.rise_db);
    residual_armed_ = false;
    if ((n - candidate_.peak_frame >= frames_.peak && n - candidate_.frame >= frames_.peak) ||
        n - candidate_.frame >= frames_.max_open) {
      // Closed at max_open while the envelope still reached new peaks: its pick window ended at
      // the sound's peak so far and found its onset; a candidate opening right after is the
      // rest of the same sound, whose own window cannot reach back past that peak.
      still_rising_until_ = n - candidate_.peak_frame < frames_.peak ? n + frames_.peak : -1;
      open_ = false;
      candidate_.closed_at = n;
      candidate_.closed_in_block = k;
      return candidate_;
    }
    return std::nullopt;
  }
  // No re-arming hysteresis in the bands: a sound that keeps rising (a precursor growing into
  // the hit) opens a new candidate every peak window, and the merger keeps the loudest of them.
  if (band.rise_db >= secondary_threshold_db_ ||
      (residual_armed_ && residual.rise_db >= secondary_threshold_db_)) {
    const std::int64_t m = n - frames_.attack;
    open_ = true;
    candidate_ = Candidate{};
    candidate_.continues = n <= still_rising_until_;
    candidate_.frame = m;
    candidate_.rise_db = band.rise_db;
    candidate_.band = band.band;
    candidate_.residual_rise_db = residual.rise_db;
    const EnvelopeBand& level = bands_.band(0);
    candidate_.peak_db = level.Db(m);
    candidate_.peak_frame = m;
    for (std::int64_t i = m + 1; i <= n; ++i) {
      if (level.Db(i) > candidate_.peak_db) {
        candidate_.peak_db = level.Db(i);
        candidate_.peak_frame = i;
      }
    }
  }
  return std::nullopt;
}

std::optional<Candidate> CandidateTracker::Finish(std::int64_t last) {
  if (!open_) return std::nullopt;
  open_ = false;
  candidate_.closed_at = last;
  candidate_.closed_in_block = -1;
  return candidate_;
}

}  // namespace bouncecal::audio
