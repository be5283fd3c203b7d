#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_ENVELOPES_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_ENVELOPES_H_

#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "detector/band_filter.h"
#include "detector/detector_frames.h"
#include "detector/noise_floor.h"
#include "detector/power_db.h"
#include "detector/sample_history.h"
#include "detector/window_max.h"

namespace bouncecal::audio {

// -140 dBFS: the floor of every envelope in dB.
inline constexpr double kTinyPower = 1e-14;
inline double EnvelopeDb(double power) { return PowerToDb(std::max(power, kTinyPower)); }

// 10 log10 of a window's maximum power, converted only when that maximum changes: converting
// every frame of every band was a third of the detector's time, and a window's maximum stays
// the same for many frames. (The dB of the maximum power is the maximum of the dBs: PowerToDb
// is monotonic to within its 1e-9 dB.)
class MaxDb {
 public:
  double operator()(double power) {
    if (power != power_) {  // NaN before the first: always unequal
      power_ = power;
      db_ = EnvelopeDb(power);
    }
    return db_;
  }

 private:
  double power_ = std::numeric_limits<double>::quiet_NaN();
  double db_ = 0;
};

// One detection band: its filtered samples, energy frames, noise floor and rise windows.
struct EnvelopeBand {
  // The frame ring has a power-of-two size so indexing is a mask, not a division. Frames are
  // kept as powers; Db() converts the few that candidates look at.
  // window_history: the frames before a block that its rise windows reach back to.
  EnvelopeBand(std::size_t history, std::size_t frames, double frame_s, std::size_t window_history)
      : samples(history),
        frame_powers_ring(std::bit_ceil(frames)),
        mask(frame_powers_ring.size() - 1),
        floor(frame_s),
        window_frames(window_history, -std::numeric_limits<double>::infinity()) {}
  SampleHistory<float> samples;
  std::vector<double> frame_powers_ring;  // mean squares of the recent frames
  std::size_t mask;
  NoiseFloor floor;
  double power = 0;  // of the frame being filled
  // Mean squares of the frames completed by this block: in window_frames, after their history.
  std::span<const double> frame_powers;
  // Per frame of this block, the window maxima and the floor as they stood at that frame: the
  // windows and the floor run over the whole block in one tight loop per band, and the frame
  // being examined reads its state from here.
  std::vector<double> ahead_maxima;
  std::vector<double> reference_maxima;
  std::vector<double> floor_powers;
  double Power(std::int64_t frame) const {
    return frame_powers_ring[static_cast<std::size_t>(frame) & mask];
  }
  double Db(std::int64_t frame) const { return EnvelopeDb(Power(frame)); }
  // The frames the rise windows of a block read, from window_start: the window_history frames
  // before it (minus infinity before the first frame, which no maximum takes), then the block's.
  // The frames are written here as they are summed, and the next block's history is the end of
  // this one's: it moves to the front only when the next block's frames would not fit after it.
  std::vector<double> window_frames;
  std::size_t window_start = 0;
  // Maxima of the attack window [m, n] and the lookback [m - lookback, m - skip] (see
  // BandEnvelopes::Rise) as they stand after the last frame so far (minus infinity before it).
  double ahead_latest = -std::numeric_limits<double>::infinity();
  double reference_latest = -std::numeric_limits<double>::infinity();
  MaxDb ahead_db;
  MaxDb reference_db;
  // The state at frame k of the block (k >= 0), else the latest.
  double AheadMax(std::ptrdiff_t k) const {
    return k < 0 ? ahead_latest : ahead_maxima[static_cast<std::size_t>(k)];
  }
  double ReferenceMax(std::ptrdiff_t k) const {
    return k < 0 ? reference_latest : reference_maxima[static_cast<std::size_t>(k)];
  }
  double FloorDb(std::ptrdiff_t k) const {
    return k < 0 ? floor.db() : NoiseFloor::ToDb(floor_powers[static_cast<std::size_t>(k)]);
  }
};

// Stage 1 of the impact detector: the recording through the causal band-pass (band 0) and
// high-passed sub-bands (a new impact brings fresh high-frequency energy while the tail of the
// previous one is mostly low modes, whose damping is lower), and a low band (band 0 up to 2 kHz,
// for a bounce under a hiss that fills the others: OnsetLocator::Locate), each cut into energy
// frames with a minimum-statistics noise floor and the two windows of the rise test. Memory is
// fixed: every band keeps its recent samples and frames in rings.
//
// The filter delivers whole blocks; Filter() returns how many samples it delivered, and the
// frames they completed are then examined in order with the block-relative index k (0 for the
// first frame the block completed), before the next call.
class BandEnvelopes {
 public:
  // secondary_rise_db: the smallest rise the caller asks about (see AnyBandMayRise);
  // frame_ring_extra: frames beyond the lookback that the caller reads back from the newest;
  // history_samples, band_zero_history: samples each band, and band 0, must hold before the
  // frames being examined (band 0 also serves the ringing residual, which reads further back).
  BandEnvelopes(const DetectorFrames& frames, const DetectorOptions& options,
                double secondary_rise_db, std::int64_t frame_ring_extra,
                std::size_t history_samples, std::size_t band_zero_history);
  BandEnvelopes(const BandEnvelopes&) = delete;
  BandEnvelopes& operator=(const BandEnvelopes&) = delete;

  // Filters `samples` (at most max_latency_samples() at once) and returns how many filtered
  // samples it delivered (0 while the filter fills its block).
  std::size_t Filter(std::span<const float> samples);
  // The filter's remaining samples at the end of the stream.
  std::size_t Finish();
  std::size_t max_latency_samples() const { return filter_.max_latency_samples(); }

  std::size_t size() const { return bands_.size(); }
  // The band's lower edge: band 0's high-pass (also the low band's), the sub-bands' extra
  // high-pass.
  double low_hz(std::size_t b) const { return low_hz_[b]; }
  // Band 0 and its high-passed sub-bands come first; a low band (band 0 low-passed), where
  // present, is the last.
  std::size_t high_pass_bands() const { return high_pass_bands_; }
  bool is_low_band(std::size_t b) const { return b >= high_pass_bands_; }
  EnvelopeBand& band(std::size_t b) { return bands_[b]; }
  const EnvelopeBand& band(std::size_t b) const { return bands_[b]; }
  // Frames completed before the latest delivered block, and how far the frame then being
  // filled was (the first frame of the block completes after hop - fill of its samples).
  std::int64_t frames_before_block() const { return frames_before_block_; }
  std::int64_t fill_before_block() const { return fill_before_block_; }

  // Rise in dB of frame m = n - attack of band b, n the block's frame k: its loudest frame in
  // the attack window [m, n] against the loudest frame of the lookback [m - lookback, m - skip].
  double Rise(std::size_t b, std::ptrdiff_t k) {
    EnvelopeBand& band = bands_[b];
    return band.ahead_db(band.AheadMax(k)) - band.reference_db(band.ReferenceMax(k));
  }
  // Whether some band's rise at frame k might reach secondary_rise_ratio, tested on the powers:
  // outside candidates the rises only matter there, and the dB conversions they need were a
  // third of the frame loop. The margin covers PowerToDb's 1e-9 dB, so every frame whose rise in
  // dB reaches the threshold passes, and the decisions are exactly those of comparing every rise.
  bool AnyBandMayRise(std::ptrdiff_t k) const {
    return may_rise_[static_cast<std::size_t>(k)] != 0;
  }

 private:
  void Take(std::size_t b, std::span<const float> samples);
  void EndBlock();

  const DetectorFrames frames_;
  BandFilter filter_;
  BandFilter::Sink sink_;  // Take, for the filter
  double secondary_rise_ratio_;
  std::size_t ahead_frames_;      // the attack window's length
  std::size_t reference_frames_;  // the lookback's
  std::size_t window_history_;    // frames before a block that the windows read
  std::vector<EnvelopeBand> bands_;
  std::vector<double> low_hz_;
  std::size_t high_pass_bands_ = 0;
  std::size_t delivered_ = 0;
  std::vector<std::int64_t> may_rise_;  // per frame of the block: some band may rise
  std::vector<double> window_scratch_;  // WindowMaxima's
  bool taken_ = false;                  // some band took samples since the last EndBlock
  // Scratch for NoiseFloor::AddBlocks: every band's floor, frame powers and floor outputs.
  std::vector<NoiseFloor*> floors_;
  std::vector<std::span<const double>> floor_inputs_;
  std::vector<double*> floor_outputs_;
  std::int64_t frames_before_block_ = 0;
  std::int64_t fill_before_block_ = 0;
  std::int64_t fill_ = 0;         // samples in the frame being filled
  std::int64_t frame_count_ = 0;  // frames completed
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_BAND_ENVELOPES_H_
