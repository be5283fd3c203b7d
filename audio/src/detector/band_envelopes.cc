#include "detector/band_envelopes.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "detector/frame_energy.h"

namespace bouncecal::audio {
namespace {

// High-pass edges of the extra detection bands; a band is used when its edge is above the main
// band's low edge and below 0.7 of the Nyquist frequency (and the low-pass).
constexpr double kDetectionBandsHz[] = {2000.0, 6000.0};

std::vector<double> DetectionBands(int rate, const DetectorOptions& options) {
  std::vector<double> edges;
  for (double hz : kDetectionBandsHz) {
    if (hz > options.band_low_hz * 1.5 && hz < 0.35 * rate &&
        (options.band_high_hz <= 0 || hz < 0.5 * options.band_high_hz)) {
      edges.push_back(hz);
    }
  }
  return edges;
}

// Upper edge of the low detection band (band_low_hz up to it): speech's sibilants and a room's
// hiss fill the bands above a few kHz for many milliseconds, so a bounce among them rises only in
// the band's low part (zaky-ptv's first bounce, docs/codecs.md).
constexpr double kLowBandHighHz = 2000.0;

double LowBandHighHz(int rate, const DetectorOptions& options) {
  const bool fits = kLowBandHighHz > options.band_low_hz * 1.5 && kLowBandHighHz < 0.35 * rate &&
                    (options.band_high_hz <= 0 || kLowBandHighHz < 0.5 * options.band_high_hz);
  return fits ? kLowBandHighHz : 0.0;
}

// may_rise[k] |= (the attack window's maximum reaches ratio times the lookback's at frame k),
// on the powers floored like EnvelopeDb's. On plain pointers to flags as wide as the powers:
// over the members and char flags (a char may alias anything) every pointer was loaded again
// for every frame, and the comparisons were not vectorised. Also compiled for AVX, picked when
// the library loads where the processor has it (the baseline instruction set has no vector of
// these comparisons); a comparison is exact either way.
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target_clones("avx", "default")]]
#endif
void MarkMayRise(const double* __restrict ahead, const double* __restrict reference, double ratio,
                 std::size_t count, std::int64_t* __restrict may_rise) {
  const double tiny = kTinyPower;
  for (std::size_t k = 0; k < count; ++k) {
    const double a = ahead[k], r = reference[k];
    may_rise[k] |= std::max(a, tiny) >= ratio * std::max(r, tiny) ? 1 : 0;
  }
}

}  // namespace

BandEnvelopes::BandEnvelopes(const DetectorFrames& frames, const DetectorOptions& options,
                             double secondary_rise_db, std::int64_t frame_ring_extra,
                             std::size_t history_samples, std::size_t band_zero_history)
    : frames_(frames),
      filter_(frames.rate_hz, options.band_low_hz, options.band_high_hz,
              DetectionBands(frames.rate_hz, options), LowBandHighHz(frames.rate_hz, options)),
      secondary_rise_ratio_(std::pow(10.0, 0.1 * secondary_rise_db) * (1.0 - 1e-6)),
      ahead_frames_(static_cast<std::size_t>(frames.attack + 1)),
      reference_frames_(
          static_cast<std::size_t>(std::max<std::int64_t>(1, frames.lookback - frames.skip + 1))),
      // The attack window of frame n reaches back to n - attack, the lookback to
      // n - attack - skip - (reference frames - 1).
      window_history_(
          std::max(ahead_frames_ - 1,
                   static_cast<std::size_t>(frames.attack + frames.skip) + reference_frames_ - 1)) {
  sink_ = [this](std::size_t band, std::span<const float> samples) { Take(band, samples); };
  // The frames the windows read plus the caller's, plus a whole filter block: a block's frames
  // are entered before they are examined.
  const auto ring = static_cast<std::size_t>(
      frames.lookback + frame_ring_extra +
      static_cast<std::int64_t>(filter_.max_latency_samples()) / frames.hop + 1);
  low_hz_.push_back(options.band_low_hz);
  for (double hz : DetectionBands(frames.rate_hz, options)) low_hz_.push_back(hz);
  high_pass_bands_ = low_hz_.size();
  if (LowBandHighHz(frames.rate_hz, options) > 0) low_hz_.push_back(options.band_low_hz);
  // The low band's floor is never read (its rises open nothing and name no band whose SNR is
  // measured): the floors are kept for the other bands only.
  floors_.resize(high_pass_bands_);
  floor_inputs_.resize(high_pass_bands_);
  floor_outputs_.resize(high_pass_bands_);
  for (std::size_t b = 0; b < filter_.output_count(); ++b) {
    // Each band's history holds a whole filter block ahead of the frames being examined.
    const std::size_t history =
        (b == 0 ? band_zero_history : history_samples) + filter_.max_latency_samples();
    bands_.emplace_back(history, ring, frames.frame_s, window_history_);
  }
}

std::size_t BandEnvelopes::Filter(std::span<const float> samples) {
  delivered_ = 0;
  filter_.Process(samples, sink_);
  EndBlock();
  return delivered_;
}

std::size_t BandEnvelopes::Finish() {
  delivered_ = 0;
  filter_.Finish(sink_);
  EndBlock();
  return delivered_;
}

void BandEnvelopes::EndBlock() {
  // The floors of every band's frames of this block, side by side (NoiseFloor::AddBlocks); the
  // frames are examined only after this.
  if (taken_) {
    for (std::size_t b = 0; b < floors_.size(); ++b) {
      floors_[b] = &bands_[b].floor;
      floor_inputs_[b] = bands_[b].frame_powers;
      floor_outputs_[b] = bands_[b].floor_powers.data();
    }
    NoiseFloor::AddBlocks(floors_, floor_inputs_, floor_outputs_);
    taken_ = false;
  }
  frames_before_block_ = frame_count_;
  fill_before_block_ = fill_;
  const auto completed = (fill_ + static_cast<std::int64_t>(delivered_)) / frames_.hop;
  frame_count_ += completed;
  fill_ = (fill_ + static_cast<std::int64_t>(delivered_)) % frames_.hop;
}

// Blocks of frames window_frames has room for after the history (a few hundred doubles).
constexpr std::size_t kWindowBlocks = 8;

// One band's share of a filtered block, straight from the filter's buffer (no intermediate
// copy): its history takes the whole block and its frame energies are collected, band by band
// (cache-friendly loops), before the frames are examined. Every band's block covers the same
// samples, so each starts at the frame fill the previous block left.
void BandEnvelopes::Take(std::size_t b, std::span<const float> samples) {
  EnvelopeBand& band = bands_[b];
  taken_ = true;
  band.samples.PushBlock(samples);
  const auto hop = static_cast<std::size_t>(frames_.hop);
  // At most one frame more than the block holds whole: the one the last block left unfinished.
  const std::size_t most = samples.size() / hop + 1;
  std::vector<double>& frames = band.window_frames;
  if (band.window_start + window_history_ + most > frames.size()) {
    if (band.window_start > 0) {
      std::copy(frames.begin() + static_cast<std::ptrdiff_t>(band.window_start),
                frames.begin() + static_cast<std::ptrdiff_t>(band.window_start + window_history_),
                frames.begin());
      band.window_start = 0;
    }
    // Room for several blocks, so the history moves once in several blocks.
    frames.resize(std::max(frames.size(), window_history_ + kWindowBlocks * most));
  }
  double* const out = frames.data() + band.window_start + window_history_;
  std::size_t count = 0;
  auto fill = static_cast<std::size_t>(fill_);
  double power = band.power;
  // The frame the last block left unfinished, the whole frames in a plain loop, and the start
  // of the next one: the same sums in the same order as frame by frame.
  std::size_t at = std::min(samples.size(), fill > 0 ? hop - fill : 0);
  power += SumOfSquares(samples.first(at));
  fill += at;
  if (fill == hop) {
    out[count++] = power / static_cast<double>(frames_.hop);
    power = 0;
    fill = 0;
  }
  if (fill == 0) {
    const std::size_t whole = (samples.size() - at) / hop;
    FrameMeanSquares(samples.data() + at, hop, whole, out + count);
    count += whole;
    at += whole * hop;
    power = SumOfSquares(samples.subspan(at));
    fill = samples.size() - at;
  }
  band.frame_powers = {out, count};
  band.power = power;
  delivered_ = samples.size();
  // The frame ring and the rise windows of the block's frames, and whether the band may rise
  // there: none of it depends on the decisions made frame by frame, so it runs here in one loop
  // per band instead of interleaved with them (the floors run for all bands at once, EndBlock).
  band.ahead_maxima.resize(count);
  band.reference_maxima.resize(count);
  band.floor_powers.resize(count);
  if (b == 0) may_rise_.assign(count, 0);
  // In the ring's contiguous runs (at most two), not one masked store per frame.
  for (std::size_t k = 0; k < count;) {
    const std::size_t at = (static_cast<std::size_t>(frame_count_) + k) & band.mask;
    const std::size_t run = std::min(count - k, band.frame_powers_ring.size() - at);
    std::copy_n(band.frame_powers.begin() + static_cast<std::ptrdiff_t>(k), run,
                band.frame_powers_ring.begin() + static_cast<std::ptrdiff_t>(at));
    k += run;
  }
  // Rise of frame m = n - attack: the attack window [m, n] and the lookback
  // [m - lookback, m - skip] = [n - lag - (reference frames - 1), n - lag], both over the
  // block's frames after the history's, all of the block at once.
  const std::span<const double> all(frames.data() + band.window_start, window_history_ + count);
  const auto lag = static_cast<std::size_t>(frames_.attack + frames_.skip);
  if (count > 0) {
    // Both windows in one call, the shorter first: they share its passes.
    std::array<WindowRun, 2> runs = {
        WindowRun{window_history_ - (ahead_frames_ - 1), ahead_frames_, band.ahead_maxima},
        WindowRun{window_history_ - lag - (reference_frames_ - 1), reference_frames_,
                  band.reference_maxima}};
    if (runs[1].window < runs[0].window) std::swap(runs[0], runs[1]);
    WindowMaxima(all, runs, window_scratch_);
    band.ahead_latest = band.ahead_maxima.back();
    band.reference_latest = band.reference_maxima.back();
  }
  band.window_start += count;
  // The low band opens no candidate (NoveltyRise::low_band_rise_db): it is read only while one is
  // open, and the frames outside candidates stay decided by the other bands' rises alone.
  if (is_low_band(b)) return;
  MarkMayRise(band.ahead_maxima.data(), band.reference_maxima.data(), secondary_rise_ratio_, count,
              may_rise_.data());
}

}  // namespace bouncecal::audio
