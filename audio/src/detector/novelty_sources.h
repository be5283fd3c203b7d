#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_NOVELTY_SOURCES_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_NOVELTY_SOURCES_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "detector/band_envelopes.h"
#include "detector/detector_frames.h"
#include "detector/noise_floor.h"
#include "detector/ringing_residual.h"

namespace bouncecal::audio {

// How far the sound at frame m = n - attack rose above what came before it, on the scale of
// rise_threshold_db, and the detection band in which its onset is best picked.
struct NoveltyRise {
  double rise_db = -std::numeric_limits<double>::infinity();
  std::size_t band = 0;
  // The ringing residual's rise counted only over what a transform codec did not leave out and
  // code again (RingingResidual::CodecNoveltyDb; rise_db itself in other files). Only the
  // residual sets it.
  double codec_rise_db = -std::numeric_limits<double>::infinity();
  // The low band's rise (BandEnvelopes::is_low_band), outside rise_db and band: it neither opens
  // a candidate nor names the band its onset is picked in. Only the band rise sets it.
  double low_band_rise_db = -std::numeric_limits<double>::infinity();
};

// Stage 2 of the impact detector: a measure of new sound, frame by frame. Every source is
// asked about every frame in order; a candidate opens where one of them rises (see
// CandidateTracker).
class NoveltySource {
 public:
  virtual ~NoveltySource() = default;
  // Called once for every envelope frame n, in order, before Rise; k is n's index in the block
  // the band envelopes delivered last.
  virtual void EnterFrame(std::int64_t n, std::ptrdiff_t k) = 0;
  // The rise of frame m = n - attack. Where `wanted` is false the caller only needs to know
  // whether it reaches the secondary threshold, and a source may answer minus infinity below it.
  virtual NoveltyRise Rise(std::int64_t n, std::ptrdiff_t k, bool wanted) = 0;
};

// The rise of the band envelopes: in each band, the loudest frame of the attack window against
// the loudest of the lookback; the band that rose most wins. Because the reference is what was
// there just before, a ringing tail raises the bar by itself, and an echo within the lookback
// of a louder hit never rises above it.
class RingingResidualNovelty;

class BandRiseNovelty final : public NoveltySource {
 public:
  // With a residual, a sub-band over which the recording holds less than half an octave of
  // content (UsableBands) neither rises nor names the band of a rise.
  explicit BandRiseNovelty(BandEnvelopes& bands, const RingingResidualNovelty* residual = nullptr)
      : bands_(bands), residual_(residual) {}
  void EnterFrame(std::int64_t, std::ptrdiff_t) override {}
  // The test that rules out most frames inline, the rises out of line (as for the residual).
  NoveltyRise Rise(std::int64_t, std::ptrdiff_t k, bool wanted) override {
    if (!wanted && !bands_.AnyBandMayRise(k)) return NoveltyRise{};
    return Rises(k);
  }

 private:
  NoveltyRise Rises(std::ptrdiff_t k);

  BandEnvelopes& bands_;
  const RingingResidualNovelty* residual_;
};

// How many of the bands, from band 0 up, hold at least half an octave of the recording's content:
// a codec or a phone path that cut the spectrum just above a detection band's edge leaves that
// band a sliver (the 6 kHz band of a recording band-limited at 6.3-7.1 kHz), whose zero-phase
// low-pass rings for milliseconds before every impact. Rises there opened candidates and timed
// onsets 0.3-1.1 ms early (10-18 stated sigmas in the random-impairment sweep).
std::size_t UsableBands(const BandEnvelopes& bands, double content_edge_hz);

// New energy that the decaying ringing of earlier impacts does not explain (the per-bin
// spectral novelty of ringing_residual.h) on band 0: finds impacts buried in a long-ringing
// plate's tail, where no band energy rises. It is only consulted where a tail is present: where
// band 0's recent level is near the noise the band rises are as sensitive, and the residual
// would only split a hit that builds up slowly into two candidates. It also measures the noise
// under the ringing (its floor), against which an impact inside a tail is checked.
class RingingResidualNovelty final : public NoveltySource {
 public:
  // The residual reads band 0's sample history, which must hold
  // RingingResidual::HistorySamples(rate) samples.
  RingingResidualNovelty(const DetectorFrames& frames, const DetectorOptions& options,
                         BandEnvelopes& bands, std::size_t frame_ring);

  // The residual advances with the samples the band envelopes delivered, in runs that end at
  // its frame boundaries.
  std::size_t samples_to_frame() const { return residual_.samples_to_frame(); }
  void Advance(std::size_t samples) {
    if (residual_.Advance(samples)) noise_power_ = residual_.noise_power();
  }

  // Inline, like Rise's tail test: it runs for every frame.
  void EnterFrame(std::int64_t n, std::ptrdiff_t) override {
    latest_frame_[static_cast<std::size_t>(n) & mask_] = residual_.latest_frame();
    if (!std::isnan(noise_power_)) noise_floor_.Add(noise_power_);
  }
  // band is 0; minus infinity where no tail is present or the novelty stays below the
  // secondary threshold. The tail test inline: it rules out most frames, and a call per frame
  // cost more than the test.
  NoveltyRise Rise(std::int64_t n, std::ptrdiff_t k, bool) override {
    if (!TailPresent(k)) return NoveltyRise{};
    return RiseInTail(n);
  }

  // A level in band 0 (dB) against the noise under the ringing, or minus infinity before that
  // noise was measured.
  double SnrDb(double level_db) const;
  int window_samples() const { return residual_.window_samples(); }
  int hop_samples() const { return residual_.hop_samples(); }
  // The highest frequency the recording has held content at so far (RingingResidual).
  double content_edge_hz() const { return residual_.content_edge_hz(); }
  // The residual's novelty in its own unit (mean per-bin rise in dB) for a rise on the band
  // scale.
  double NoveltyDb(double rise_db) const;

 private:
  // A tail is present where band 0's lookback stands rise_threshold_db above the noise under the
  // ringing (under continuous ringing the band's own minimum-statistics floor is the ringing).
  // Decided on the powers (the same clamps as EnvelopeDb and NoiseFloor::db) where they are
  // clearly apart, in dB only within a margin around the threshold that covers PowerToDb's
  // 1e-9 dB: the same decision as in dB, without the conversions and their data-dependent
  // branches in every frame.
  bool TailPresent(std::ptrdiff_t k) {
    if (!noise_floor_.started()) return false;
    const double reference = std::max(bands_.band(0).ReferenceMax(k), kTinyPower);
    const double floor = std::max(noise_floor_.power(), kTinyPower) * tail_ratio_;
    if (reference >= floor * (1.0 + 1e-6)) return true;
    if (reference >= floor * (1.0 - 1e-6)) return TailPresentInDb(k);
    return false;
  }
  bool TailPresentInDb(std::ptrdiff_t k);
  NoveltyRise RiseInTail(std::int64_t n);
  // The loudest novelty of the residual frames that envelope frames [m, n] hold, and the loudest
  // CodecNoveltyDb of them.
  std::pair<double, double> MaxNoveltyDb(std::int64_t m, std::int64_t n);

  const DetectorFrames frames_;
  double rise_threshold_db_;
  double secondary_threshold_db_;
  double tail_ratio_;  // the power ratio of rise_threshold_db
  BandEnvelopes& bands_;
  RingingResidual residual_;
  // Per envelope frame (a ring like the bands'), the latest residual frame that ended in it or
  // before (-1 before the first): only these frames' spectra and their lookbacks are computed,
  // so the residual costs little outside tails.
  std::vector<std::int64_t> latest_frame_;
  std::size_t mask_;
  NoiseFloor noise_floor_;  // of the noise under the ringing, one entry per envelope frame
  double noise_power_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_NOVELTY_SOURCES_H_
