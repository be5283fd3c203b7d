#include "detector/novelty_sources.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace bouncecal::audio {
namespace {

// The ringing residual's novelty (mean per-bin rise in dB, see ringing_residual.h) that counts
// as a full rise_threshold_db: it is rescaled so the user's threshold moves both tests together.
// Stationary noise gives 0.2-0.3 dB and the loudest beating plate tail measured ~0.4 dB (free
// Kirchhoff plate, 12 drops); an impact that lifts a tenth of the bins by 6 dB gives 0.6 dB.
constexpr double kNoveltyAtThresholdDb = 0.6;

}  // namespace

std::size_t UsableBands(const BandEnvelopes& bands, double content_edge_hz) {
  // 2^-1/2: a band's low edge must lie half an octave under the content edge.
  constexpr double kMinContentOctaveRatio = 0.70710678118654752;
  std::size_t usable = 1;
  while (usable < bands.high_pass_bands() &&
         bands.low_hz(usable) <= content_edge_hz * kMinContentOctaveRatio) {
    ++usable;
  }
  return usable;
}

NoveltyRise BandRiseNovelty::Rises(std::ptrdiff_t k) {
  NoveltyRise rise;
  const std::size_t usable =
      residual_ ? UsableBands(bands_, residual_->content_edge_hz()) : bands_.high_pass_bands();
  for (std::size_t b = 0; b < usable; ++b) {
    const double db = bands_.Rise(b, k);
    if (db > rise.rise_db) {
      rise.rise_db = db;
      rise.band = b;
    }
  }
  for (std::size_t b = bands_.high_pass_bands(); b < bands_.size(); ++b) {
    rise.low_band_rise_db = std::max(rise.low_band_rise_db, bands_.Rise(b, k));
  }
  return rise;
}

RingingResidualNovelty::RingingResidualNovelty(const DetectorFrames& frames,
                                               const DetectorOptions& options, BandEnvelopes& bands,
                                               std::size_t frame_ring)
    : frames_(frames),
      rise_threshold_db_(options.rise_threshold_db),
      secondary_threshold_db_(kSecondaryRiseFraction * options.rise_threshold_db),
      tail_ratio_(std::pow(10.0, 0.1 * options.rise_threshold_db)),
      bands_(bands),
      residual_(frames.rate_hz, options.band_low_hz, options.band_high_hz, &bands.band(0).samples),
      latest_frame_(std::bit_ceil(frame_ring), -1),
      mask_(latest_frame_.size() - 1),
      noise_floor_(frames.frame_s) {
  // Under the secondary threshold a novelty opens nothing, and the codec's floor is not needed.
  residual_.set_transform_coded(options.transform_coded,
                                kSecondaryRiseFraction * kNoveltyAtThresholdDb);
}

bool RingingResidualNovelty::TailPresentInDb(std::ptrdiff_t k) {
  EnvelopeBand& band = bands_.band(0);
  return band.reference_db(band.ReferenceMax(k)) - noise_floor_.db() >= rise_threshold_db_;
}

NoveltyRise RingingResidualNovelty::RiseInTail(std::int64_t n) {
  NoveltyRise rise;
  const auto [novelty_db, codec_novelty_db] = MaxNoveltyDb(n - frames_.attack, n);
  const double scale = rise_threshold_db_ / kNoveltyAtThresholdDb;
  if (novelty_db * scale >= secondary_threshold_db_) {
    rise.rise_db = novelty_db * scale;
    rise.codec_rise_db = codec_novelty_db * scale;
  }
  return rise;
}

std::pair<double, double> RingingResidualNovelty::MaxNoveltyDb(std::int64_t m, std::int64_t n) {
  double novelty_db = -std::numeric_limits<double>::infinity();
  double codec_novelty_db = -std::numeric_limits<double>::infinity();
  const auto novelty_of = [&](std::int64_t frame) {
    if (frame < 0) {
      codec_novelty_db = std::max(codec_novelty_db, 0.0);
      return 0.0;
    }
    codec_novelty_db = std::max(codec_novelty_db, residual_.CodecNoveltyDb(frame));
    return residual_.NoveltyDb(frame);
  };
  // The latest residual frame never decreases from one envelope frame to the next: where the
  // window's first and last are the same frame or neighbours, they are all the frames it holds,
  // taken in the same order as below without the walk over every envelope frame (a residual hop
  // spans 7 envelope frames at 48 kHz, so nearly every window is such).
  const std::int64_t first = latest_frame_[static_cast<std::size_t>(m) & mask_];
  const std::int64_t last = latest_frame_[static_cast<std::size_t>(n) & mask_];
  if (last - first <= 1) {
    novelty_db = std::max(novelty_db, novelty_of(first));
    if (last != first) novelty_db = std::max(novelty_db, novelty_of(last));
    return {novelty_db, codec_novelty_db};
  }
  std::int64_t previous = -2;
  for (std::int64_t i = m; i <= n; ++i) {
    const std::int64_t frame = latest_frame_[static_cast<std::size_t>(i) & mask_];
    if (frame == previous) continue;
    previous = frame;
    novelty_db = std::max(novelty_db, novelty_of(frame));
  }
  return {novelty_db, codec_novelty_db};
}

double RingingResidualNovelty::SnrDb(double level_db) const {
  if (!noise_floor_.started()) return -std::numeric_limits<double>::infinity();
  return level_db - noise_floor_.db();
}

double RingingResidualNovelty::NoveltyDb(double rise_db) const {
  return rise_db * kNoveltyAtThresholdDb / rise_threshold_db_;
}

}  // namespace bouncecal::audio
