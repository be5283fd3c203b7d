#include "bouncecal/audio/impact_detector.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "band_filter.h"
#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/error.h"
#include "noise_floor.h"
#include "onset_picker.h"
#include "power_db.h"
#include "prediction_innovation.h"
#include "ringing_residual.h"
#include "sample_history.h"
#include "window_max.h"

namespace bouncecal::audio {
namespace {

constexpr double kTinyPower = 1e-14;  // -140 dBFS: the floor of the envelope in dB
// The rise is measured against frames at least this far back, so the first frames of a rise do
// not serve as their own reference.
constexpr double kRiseSkipMs = 0.5;
// How long an impact may take to build up its rise (see OnFrame).
constexpr double kAttackMs = 2.0;
// After the first rising frame, the envelope peak of the impact is searched this long.
constexpr double kPeakSearchMs = 3.0;
static_assert(kPeakSearchMs > kAttackMs);
// A candidate that keeps rising is closed after min_gap_ms, at most this long.
constexpr double kMaxOpenMs = 50.0;
// Noise before the onset that the AIC picker sees (bounded by the previous impact's peak).
constexpr double kPickerNoiseMs = 4.0;
// Window after the onset in which peak_dbfs is measured.
constexpr double kPeakLevelMs = 5.0;
// Rises of this fraction of rise_threshold_db open a candidate; it counts as an impact only
// if it or a member of its min-gap group reaches the full threshold (see Merge).
constexpr double kSecondaryRiseFraction = 0.5;
// Order of the linear predictor that removes ringing before picking an onset inside it: two
// coefficients per mode, so up to 12 modes in the band (a plate's strong low modes).
constexpr int kInnovationOrder = 24;
// The ringing residual's novelty (mean per-bin rise in dB, see ringing_residual.h) that counts
// as a full rise_threshold_db: it is rescaled so the user's threshold moves both tests together.
// Stationary noise gives 0.2-0.3 dB and the loudest beating plate tail measured ~0.4 dB (free
// Kirchhoff plate, 12 drops); an impact that lifts a tenth of the bins by 6 dB gives 0.6 dB.
constexpr double kNoveltyAtThresholdDb = 0.6;
// History kept for the picker and the peak level; longer than every window above together.
constexpr double kHistoryS = 0.1;

double ToDb(double power) { return PowerToDb(std::max(power, kTinyPower)); }

// Sum of x^2 in double (each square exact) in four interleaved partial sums: one running sum is
// a chain of dependent additions, four times the latency per sample, and it was the detector's
// largest single cost outside the FFTs. The order of the additions changes the sum by a few
// units in the last place of a double only.
double SumOfSquares(std::span<const float> x) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  std::size_t i = 0;
  for (; i + 4 <= x.size(); i += 4) {
    s0 += double{x[i]} * x[i];
    s1 += double{x[i + 1]} * x[i + 1];
    s2 += double{x[i + 2]} * x[i + 2];
    s3 += double{x[i + 3]} * x[i + 3];
  }
  for (; i < x.size(); ++i) s0 += double{x[i]} * x[i];
  return (s0 + s1) + (s2 + s3);
}

void Require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError(what);
}

}  // namespace

void DetectorOptions::Validate(int sample_rate_hz) const {
  Require(sample_rate_hz >= 1000,
          "sample rate must be at least 1000 Hz, got " + std::to_string(sample_rate_hz));
  const double nyquist_hz = sample_rate_hz / 2.0;
  Require(band_low_hz > 0 && band_low_hz < 0.9 * nyquist_hz,
          "--band-low-hz must be in (0, " + std::to_string(0.9 * nyquist_hz) + ") Hz, got " +
              std::to_string(band_low_hz));
  Require(band_high_hz <= 0 || band_high_hz > band_low_hz,
          "--band-high-hz must be above --band-low-hz (or 0 for no low-pass), got " +
              std::to_string(band_high_hz));
  Require(rise_threshold_db > 0 && rise_threshold_db <= 60,
          "--rise-threshold-db must be in (0, 60] dB, got " + std::to_string(rise_threshold_db));
  Require(rise_lookback_ms >= 2 && rise_lookback_ms <= 200,
          "--rise-lookback-ms must be in [2, 200] ms, got " + std::to_string(rise_lookback_ms));
  Require(min_snr_db >= 0 && min_snr_db <= 80,
          "--min-snr-db must be in [0, 80] dB, got " + std::to_string(min_snr_db));
  Require(min_gap_ms >= 0 && min_gap_ms <= 1000,
          "--min-gap-ms must be in [0, 1000] ms, got " + std::to_string(min_gap_ms));
  Require(frame_ms * sample_rate_hz >= 1000.0 && frame_ms <= 5,
          "frame length must be at least one sample and at most 5 ms, got " +
              std::to_string(frame_ms) + " ms");
}

// High-pass edges of the extra detection bands (see OnFrame); a band is used when its edge is
// above the main band's low edge and below 0.7 of the Nyquist frequency (and the low-pass).
constexpr double kDetectionBandsHz[] = {2000.0, 6000.0};

// 10 log10 of a window's maximum power, converted only when that maximum changes: converting
// every frame of every band was a third of the detector's time, and a window's maximum stays
// the same for many frames. (The dB of the maximum power is the maximum of the dBs: PowerToDb
// is monotonic to within its 1e-9 dB.)
class MaxDb {
 public:
  double operator()(double power) {
    if (power != power_) {  // NaN before the first: always unequal
      power_ = power;
      db_ = ToDb(power);
    }
    return db_;
  }

 private:
  double power_ = std::numeric_limits<double>::quiet_NaN();
  double db_ = 0;
};

class ImpactDetector::Impl {
 public:
  Impl(int sample_rate_hz, const DetectorOptions& options)
      : rate_(sample_rate_hz),
        options_((options.Validate(sample_rate_hz), options)),
        filter_(sample_rate_hz, options.band_low_hz, options.band_high_hz,
                DetectionBands(sample_rate_hz, options)),
        raw_(static_cast<std::size_t>(Samples(kHistoryS)) + 2 * filter_.max_latency_samples()),
        hop_(std::max<std::int64_t>(1, std::llround(options.frame_ms * 1e-3 * sample_rate_hz))),
        frame_s_(static_cast<double>(hop_) / sample_rate_hz),
        lookback_frames_(Frames(options.rise_lookback_ms)),
        skip_frames_(std::max<std::int64_t>(1, Frames(kRiseSkipMs))),
        attack_frames_(Frames(kAttackMs)),
        peak_frames_(std::max(attack_frames_ + 1, Frames(kPeakSearchMs))),
        max_open_frames_(std::max(peak_frames_, Frames(std::min(options.min_gap_ms, kMaxOpenMs)))),
        secondary_threshold_db_(kSecondaryRiseFraction * options.rise_threshold_db),
        secondary_rise_ratio_(std::pow(10.0, 0.1 * secondary_threshold_db_) * (1.0 - 1e-6)),
        tail_ratio_(std::pow(10.0, 0.1 * options.rise_threshold_db)),
        bands_(MakeBands()),
        residual_(sample_rate_hz, options.band_low_hz, options.band_high_hz, &bands_[0].samples),
        residual_band_(filter_.output_count()) {
    sink_ = [this](std::size_t band, std::span<const float> samples) { Take(band, samples); };
    result_.sample_rate_hz = sample_rate_hz;
  }

  void Process(std::span<const float> samples) {
    // Feed the filter in pieces no longer than its latency so the raw history never runs more
    // than two blocks ahead of the filtered one (peak levels are read from it).
    const std::size_t piece = filter_.max_latency_samples();
    for (std::size_t at = 0; at < samples.size(); at += piece) {
      const auto part = samples.subspan(at, std::min(piece, samples.size() - at));
      raw_.PushBlock(part);
      delivered_ = 0;
      filter_.Process(part, sink_);
      Consume();
    }
  }

  DetectionResult Finish() {
    delivered_ = 0;
    filter_.Finish(sink_);
    Consume();
    if (open_) CloseCandidate();
    EmitPending();
    result_.samples = raw_.end();
    std::vector<double> snr;
    for (const auto& impact : result_.impacts) snr.push_back(impact.snr_db);
    if (snr.empty()) {
      result_.impact_to_noise_db = -std::numeric_limits<double>::infinity();
    } else {
      std::nth_element(snr.begin(), snr.begin() + static_cast<std::ptrdiff_t>(snr.size() / 2),
                       snr.end());
      result_.impact_to_noise_db = snr[snr.size() / 2];
    }
    AdoptTentative();
    return std::move(result_);
  }

 private:
  struct Pending {
    Impact impact;
    double level_db = 0;
    double group_rise_db = 0;
    double group_band_rise_db = 0;  // the same, from the filtered bands alone
    // False when no band rose by the full threshold: its level is then mostly the tail it is in.
    bool band_rose = true;
    bool continuation = false;  // the rest of a sound whose candidate was closed while rising
    std::vector<MergedEvent> others;
  };

  // One detection band: its filtered samples, energy frames and noise floor. (The residual's
  // band holds in its frame ring the latest residual frame of each envelope frame instead.)
  struct Band {
    // The frame ring has a power-of-two size so indexing is a mask, not a division. Frames are
    // kept as powers; Db() converts the few that candidates look at.
    Band(std::size_t history, std::size_t frames, double frame_s, std::size_t ahead_frames,
         std::size_t reference_frames)
        : samples(history),
          frame_powers_ring(std::bit_ceil(frames)),
          mask(frame_powers_ring.size() - 1),
          floor(frame_s),
          ahead(ahead_frames),
          reference(reference_frames) {}
    SampleHistory<float> samples;
    std::vector<double> frame_powers_ring;  // mean squares of the recent frames
    std::size_t mask;
    NoiseFloor floor;
    double power = 0;                  // of the frame being filled
    std::vector<double> frame_powers;  // mean squares of the frames completed by this block
    // Per frame of this block, the window maxima and the floor as they stood at that frame:
    // Take runs the windows and the floor over the whole block in one tight loop per band, and
    // OnFrame reads the state of the frame it examines from here.
    std::vector<double> ahead_maxima;
    std::vector<double> reference_maxima;
    std::vector<double> floor_powers;
    double Power(std::int64_t frame) const {
      return frame_powers_ring[static_cast<std::size_t>(frame) & mask];
    }
    double Db(std::int64_t frame) const { return ToDb(Power(frame)); }
    // Maxima of the attack window [m, n] and the lookback [m - lookback, m - skip] (see Rise),
    // as they stand after the block's last frame.
    WindowMax ahead;
    WindowMax reference;
    MaxDb ahead_db;
    MaxDb reference_db;
    // The state at frame k of the block while Consume examines it (k >= 0), else the latest.
    double AheadMax(std::ptrdiff_t k) const {
      return k < 0 ? ahead.max() : ahead_maxima[static_cast<std::size_t>(k)];
    }
    double ReferenceMax(std::ptrdiff_t k) const {
      return k < 0 ? reference.max() : reference_maxima[static_cast<std::size_t>(k)];
    }
    double FloorDb(std::ptrdiff_t k) const {
      return k < 0 ? floor.db() : NoiseFloor::ToDb(floor_powers[static_cast<std::size_t>(k)]);
    }
  };

  // The detection bands (filter outputs) and, last, the ringing residual's band.
  std::vector<Band> MakeBands() const {
    // The frames a candidate and the windows read, plus a whole filter block: Take enters a
    // block's frames before they are examined.
    const auto ring = static_cast<std::size_t>(
        lookback_frames_ + max_open_frames_ + peak_frames_ + attack_frames_ + 8 +
        static_cast<std::int64_t>(filter_.max_latency_samples()) / hop_ + 1);
    // The windows of Rise: [m, n] and [m - lookback, m - skip].
    const auto ahead_frames = static_cast<std::size_t>(attack_frames_ + 1);
    const auto reference_frames = static_cast<std::size_t>(lookback_frames_ - skip_frames_ + 1);
    // A band's history holds a whole filter block ahead of the frames being examined; the main
    // band's also serves the ringing residual, which reads its recent frames from it.
    const auto picker_history = static_cast<std::size_t>(Samples(kHistoryS));
    std::vector<Band> bands;
    for (std::size_t b = 0; b < filter_.output_count(); ++b) {
      const std::size_t history =
          b == 0 ? std::max(picker_history, RingingResidual::HistorySamples(rate_))
                 : picker_history;
      bands.emplace_back(history + filter_.max_latency_samples(), ring, frame_s_, ahead_frames,
                         reference_frames);
    }
    // The ringing residual has no sample stream of its own: a token history.
    bands.emplace_back(1, ring, frame_s_, 1, 1);
    return bands;
  }

  static std::vector<double> DetectionBands(int rate, const DetectorOptions& options) {
    std::vector<double> edges;
    for (double hz : kDetectionBandsHz) {
      if (hz > options.band_low_hz * 1.5 && hz < 0.35 * rate &&
          (options.band_high_hz <= 0 || hz < 0.5 * options.band_high_hz)) {
        edges.push_back(hz);
      }
    }
    return edges;
  }

  std::int64_t Samples(double seconds) const {
    return static_cast<std::int64_t>(std::ceil(seconds * rate_));
  }
  std::int64_t Frames(double ms) const {
    return std::max<std::int64_t>(1, std::llround(ms * 1e-3 * rate_ / static_cast<double>(hop_)));
  }

  // One band's share of a filtered block, straight from the filter's buffer (no intermediate
  // copy): its history takes the whole block and its frame energies are collected, band by
  // band (cache-friendly loops), before Consume examines the frames. Every band's block covers
  // the same samples, so each starts at the frame fill Consume left.
  void Take(std::size_t b, std::span<const float> samples) {
    Band& band = bands_[b];
    band.samples.PushBlock(samples);
    band.frame_powers.clear();
    const auto hop = static_cast<std::size_t>(hop_);
    auto fill = static_cast<std::size_t>(frame_fill_);
    double power = band.power;
    // The frame the last block left unfinished, the whole frames in a plain loop, and the start
    // of the next one: the same sums in the same order as frame by frame.
    std::size_t at = std::min(samples.size(), fill > 0 ? hop - fill : 0);
    power += SumOfSquares(samples.first(at));
    fill += at;
    if (fill == hop) {
      band.frame_powers.push_back(power / static_cast<double>(hop_));
      power = 0;
      fill = 0;
    }
    if (fill == 0) {
      const std::size_t whole = (samples.size() - at) / hop;
      const std::size_t first_frame = band.frame_powers.size();
      band.frame_powers.resize(first_frame + whole);
      for (std::size_t k = 0; k < whole; ++k, at += hop) {
        band.frame_powers[first_frame + k] =
            SumOfSquares(samples.subspan(at, hop)) / static_cast<double>(hop_);
      }
      power = SumOfSquares(samples.subspan(at));
      fill = samples.size() - at;
    }
    band.power = power;
    delivered_ = samples.size();
    // The frame ring, the floor and the rise windows of the block's frames, and whether the
    // band may rise there (see AnyBandMayRise): none of it depends on the decisions OnFrame
    // makes, so it runs here in one loop per band instead of interleaved with them.
    const std::size_t frames = band.frame_powers.size();
    band.ahead_maxima.resize(frames);
    band.reference_maxima.resize(frames);
    band.floor_powers.resize(frames);
    if (b == 0) may_rise_.assign(frames, 0);
    for (std::size_t k = 0; k < frames; ++k) {
      const auto n = static_cast<std::size_t>(frame_count_) + k;
      band.frame_powers_ring[n & band.mask] = band.frame_powers[k];
    }
    band.floor.AddBlock(band.frame_powers, band.floor_powers.data());
    // Rise of frame m = n - attack: the attack window [m, n] takes frame n, the lookback
    // [m - lookback, m - skip] frame m - skip once that exists (see Rise). The ring holds
    // those frames: the lookback's newest is at least attack + skip frames old.
    band.ahead.PushBlock(band.frame_powers, band.ahead_maxima.data());
    const std::int64_t lag = attack_frames_ + skip_frames_;
    const auto before_first = static_cast<std::size_t>(
        std::clamp<std::int64_t>(lag - frame_count_, 0, static_cast<std::int64_t>(frames)));
    std::fill_n(band.reference_maxima.begin(), before_first, band.reference.max());
    entering_.resize(frames - before_first);
    for (std::size_t k = before_first; k < frames; ++k) {
      entering_[k - before_first] = band.Power(frame_count_ + static_cast<std::int64_t>(k) - lag);
    }
    band.reference.PushBlock(entering_, band.reference_maxima.data() + before_first);
    for (std::size_t k = 0; k < frames; ++k) {
      may_rise_[k] |=
          static_cast<char>(std::max(band.ahead_maxima[k], kTinyPower) >=
                            secondary_rise_ratio_ * std::max(band.reference_maxima[k], kTinyPower));
    }
  }

  // Frame by frame over the samples the filter delivered (see Take).
  void Consume() {
    const std::size_t count = delivered_;
    // The residual is computed on the main band, which it reads from that band's history as far
    // as it is advanced; each envelope frame records the latest residual frame that ended in it
    // or before (a frame completed by a sample counts for that sample's envelope frame), and
    // the noise under the ringing it held. The envelope frames are examined as they complete,
    // so the residual still holds the frames they ask about.
    const bool use_residual = options_.ringing_residual;
    std::int64_t fill = frame_fill_;
    std::size_t frame = 0;
    for (std::size_t at = 0; at < count;) {
      std::size_t run = std::min(count - at, static_cast<std::size_t>(hop_ - fill));
      if (use_residual) {
        run = std::min(run, residual_.samples_to_frame());
        if (residual_.Advance(run)) residual_noise_power_ = residual_.noise_power();
      }
      at += run;
      fill += static_cast<std::int64_t>(run);
      if (fill == hop_) {
        frame_in_block_ = static_cast<std::ptrdiff_t>(frame++);
        OnFrame();
        fill = 0;
      }
    }
    frame_in_block_ = -1;
    frame_fill_ = fill;
  }

  // Rise of frame m = n - attack of one band: its loudest frame in the attack window [m, n]
  // against the loudest frame of the lookback [m - lookback, m - skip] (windows kept by Take).
  double Rise(Band& band) const {
    return band.ahead_db(band.AheadMax(frame_in_block_)) -
           band.reference_db(band.ReferenceMax(frame_in_block_));
  }
  // Whether some band's rise might reach the secondary threshold, tested on the powers: outside
  // candidates the rises only matter there, and the dB conversions they need were a third of
  // OnFrame (the attack window's maximum changes almost every frame in noise). The margin
  // covers PowerToDb's 1e-9 dB, so every frame whose rise in dB reaches the threshold passes
  // and the decisions are exactly those of comparing every rise.
  // (Computed band by band in Take.)
  bool AnyBandMayRise() const { return may_rise_[static_cast<std::size_t>(frame_in_block_)] != 0; }

  // Frame frame_in_block_ of the block: the detection bands' frames are already entered (Take).
  void OnFrame() {
    const std::int64_t n = frame_count_++;
    {
      // The residual band holds the latest residual frame (its novelty is computed only where
      // it is asked for, see ResidualNoveltyDb) and, as its floor, the noise under the ringing;
      // before its first frame there is neither (-1, NaN noise).
      Band& band = bands_[residual_band_];
      band.frame_powers_ring[static_cast<std::size_t>(n) & band.mask] =
          static_cast<double>(residual_.latest_frame());
      if (!std::isnan(residual_noise_power_)) band.floor.Add(residual_noise_power_);
    }
    if (open_) {
      const double level_db = bands_[0].Db(n);
      if (level_db > candidate_peak_db_) {
        candidate_peak_db_ = level_db;
        candidate_peak_frame_ = n;
      }
    }
    // The rise of frame m = n - attack is measured over an attack window because soft contacts
    // (tennis, rubber) take a millisecond or two to build up. It is measured in the whole band
    // and in high-passed sub-bands, and the largest counts: a new impact brings fresh
    // high-frequency energy while the tail of the previous one is mostly low modes (damping
    // grows with frequency), so inside a loud ringing tail a weaker impact still rises in the
    // high band (the idea behind aubio's high-frequency-content function, Masri 1996). The
    // first lookback of the file has no reference: the start of the file is not an impact.
    const std::int64_t m = n - attack_frames_;
    if (m < lookback_frames_) return;
    // The residual only matters where a tail is there to hide a rise: where the main band's
    // recent level is near the noise, the band rises are as sensitive and the residual would
    // only split a hit that builds up slowly into two candidates. The noise is the residual's
    // floor: under continuous ringing the band's own minimum-statistics floor is the ringing.
    // (The tail test costs a log per frame, so it is only made when the novelty could count.)
    const Band& residual = bands_[residual_band_];
    bool tail_present = false;
    if (options_.ringing_residual && residual.floor.started()) {
      // Decided on the powers (the same clamps as ToDb and NoiseFloor::db) where they are
      // clearly apart, in dB only within a margin around the threshold that covers
      // PowerToDb's 1e-9 dB: the same decision as in dB, without the conversions and their
      // data-dependent branches in every frame.
      const double reference = std::max(bands_[0].ReferenceMax(frame_in_block_), kTinyPower);
      const double floor = std::max(residual.floor.power(), kTinyPower) * tail_ratio_;
      if (reference >= floor * (1.0 + 1e-6)) {
        tail_present = true;
      } else if (reference >= floor * (1.0 - 1e-6)) {
        tail_present =
            bands_[0].reference_db(bands_[0].ReferenceMax(frame_in_block_)) - residual.floor.db() >=
            options_.rise_threshold_db;
      }
    }
    const double novelty_rise_db =
        tail_present ? ResidualNoveltyDb(m, n) * options_.rise_threshold_db / kNoveltyAtThresholdDb
                     : -std::numeric_limits<double>::infinity();
    const double residual_rise_db = novelty_rise_db >= secondary_threshold_db_
                                        ? novelty_rise_db
                                        : -std::numeric_limits<double>::infinity();
    // The ringing residual (above) is a further rise measure: inside a long-ringing tail a
    // weaker impact adds little energy to any band but is new energy the decay of the tail
    // does not predict. The onset is picked in the filtered band that rose most. The band rises
    // are needed in a candidate, where one may open, and where the residual opens one (its band
    // and rise then come from them).
    double band_rise_db = -std::numeric_limits<double>::infinity();
    std::size_t rising_band = 0;
    if (open_ || (residual_armed_ && residual_rise_db >= secondary_threshold_db_) ||
        AnyBandMayRise()) {
      for (std::size_t b = 0; b < residual_band_; ++b) {
        const double rise = Rise(bands_[b]);
        if (rise > band_rise_db) {
          band_rise_db = rise;
          rising_band = b;
        }
      }
    }
    // A residual frame spans a few ms, so after a hit it stays above its pre-hit reference for
    // that long: the residual opens a candidate only after it has fallen back below the
    // threshold once (hysteresis), never on the lingering frames of the last candidate.
    if (residual_rise_db < secondary_threshold_db_) residual_armed_ = true;
    if (open_) {
      // A candidate stays open while its envelope keeps reaching new peaks, so a hit that
      // builds up over several milliseconds (or grows out of its precursor) is one candidate
      // whose onset the picker finds; it closes peak_frames_ after its last peak.
      if (band_rise_db > candidate_rise_db_) {
        candidate_rise_db_ = band_rise_db;
        candidate_band_ = rising_band;
      }
      candidate_residual_rise_db_ = std::max(candidate_residual_rise_db_, residual_rise_db);
      if ((n - candidate_peak_frame_ >= peak_frames_ && n - candidate_frame_ >= peak_frames_) ||
          n - candidate_frame_ >= max_open_frames_) {
        // Closed at max_open while the envelope still reached new peaks: its pick window ended
        // at the sound's peak so far and found its onset; a candidate opening right after is
        // the rest of the same sound, whose own window cannot reach back past that peak.
        still_rising_until_ = n - candidate_peak_frame_ < peak_frames_ ? n + peak_frames_ : -1;
        CloseCandidate();
      }
      residual_armed_ = false;
    } else if (band_rise_db >= secondary_threshold_db_ ||
               (residual_armed_ && residual_rise_db >= secondary_threshold_db_)) {
      // No re-arming hysteresis in the bands: a sound that keeps rising (a precursor growing into
      // the hit) opens a new candidate every peak window, and Merge keeps the loudest of them.
      open_ = true;
      candidate_continues_ = n <= still_rising_until_;
      candidate_frame_ = m;
      candidate_rise_db_ = band_rise_db;
      candidate_band_ = rising_band;
      candidate_residual_rise_db_ = residual_rise_db;
      candidate_peak_db_ = bands_[0].Db(m);
      candidate_peak_frame_ = m;
      for (std::int64_t i = m + 1; i <= n; ++i) {
        if (bands_[0].Db(i) > candidate_peak_db_) {
          candidate_peak_db_ = bands_[0].Db(i);
          candidate_peak_frame_ = i;
        }
      }
    }
  }

  // The loudest novelty of the residual frames that envelope frames [m, n] hold (the latest
  // residual frame that ended in each; 0 before the first). Only these frames' spectra and
  // their lookbacks are computed, so the residual costs little outside tails.
  double ResidualNoveltyDb(std::int64_t m, std::int64_t n) {
    const Band& band = bands_[residual_band_];
    double novelty_db = -std::numeric_limits<double>::infinity();
    std::int64_t previous = -2;
    for (std::int64_t k = m; k <= n; ++k) {
      const auto frame = static_cast<std::int64_t>(band.Power(k));
      if (frame == previous) continue;
      previous = frame;
      novelty_db = std::max(novelty_db, frame < 0 ? 0.0 : residual_.NoveltyDb(frame));
    }
    return novelty_db;
  }

  // The main band's peak over the candidate against the noise under the ringing (the
  // residual's floor), or minus infinity before that floor exists.
  double ResidualSnrDb() const {
    const Band& residual = bands_[residual_band_];
    if (!residual.floor.started()) return -std::numeric_limits<double>::infinity();
    double peak_db = bands_[0].Db(candidate_frame_);
    for (std::int64_t i = candidate_frame_ + 1; i < frame_count_; ++i) {
      peak_db = std::max(peak_db, bands_[0].Db(i));
    }
    return peak_db - residual.floor.db();
  }

  void CloseCandidate() {
    open_ = false;
    const Band& band = bands_[candidate_band_];
    // SNR in the band that rose most: its loudest frame of the candidate against its floor.
    const std::int64_t last_frame = frame_count_ - 1;
    double band_peak_db = band.Db(candidate_frame_);
    for (std::int64_t i = candidate_frame_ + 1; i <= last_frame; ++i) {
      band_peak_db = std::max(band_peak_db, band.Db(i));
    }
    const double snr_db = band_peak_db - band.FloorDb(frame_in_block_);
    // Under continuous ringing the minimum-statistics floor of every band is the ringing, not
    // the noise; the ringing residual's floor stays at the noise, so passing in it also counts.
    // snr_db itself stays the band's, so the channel choice compares like with like.
    const bool band_snr_ok = snr_db >= options_.min_snr_db;
    if (!band_snr_ok && ResidualSnrDb() < options_.min_snr_db) return;
    // The onset is picked in the same band, where the impact stands out most from what was
    // there before; the window ends at the impact's largest sample.
    const SampleHistory<float>& samples = bands_[candidate_band_].samples;
    // Where no band rose by the full threshold the impact sits in a tail louder than itself, so
    // the band's largest sample and its AIC edge are the tail's: the onset is picked on the
    // prediction innovation instead (measured on the free plate: 61.9 us median against 68.6 us
    // when only rises under half the threshold took this path; the sample
    // steel_ball_h0.2m.wav's 5th impact 0.6 ms instead of 1.5 ms early).
    const bool in_ringing = candidate_rise_db_ < options_.rise_threshold_db;
    std::int64_t search_from = (candidate_frame_ - 2 * skip_frames_) * hop_;
    if (in_ringing) {
      // The residual's frame that fired ended by frame n = candidate + attack, and the onset
      // lies inside that frame's window (its Hann taper hides a new sound at the window's end,
      // so the novelty may rise a few ms after the onset): search from the window's start.
      search_from = std::min(
          search_from, (candidate_frame_ + attack_frames_ + 1) * hop_ - residual_.window_samples());
    }
    const std::int64_t search_begin = std::max(samples.begin(), search_from);
    const std::int64_t peak_end = std::min(samples.end(), (candidate_peak_frame_ + 1) * hop_);
    std::int64_t peak = search_begin;
    for (std::int64_t i = search_begin; i < peak_end; ++i) {
      if (std::fabs(samples[i]) > std::fabs(samples[peak])) peak = i;
    }
    const std::int64_t window_begin = std::max(
        {samples.begin(), search_begin - Samples(kPickerNoiseMs * 1e-3), last_peak_sample_ + 1});
    std::int64_t window_end = std::min(samples.end(), peak + 2);
    const auto begin_offset =
        static_cast<std::size_t>(std::max<std::int64_t>(0, search_begin - window_begin));
    if (in_ringing) {
      // Only the ringing residual rose: the impact is buried in the tail of earlier ones, and
      // the largest sample is the tail's, so the onset is picked on the linear-prediction
      // innovation, where the tail is removed and the impact stands out, up to its largest
      // innovation sample within the candidate.
      window_end = std::min(samples.end(), (candidate_peak_frame_ + peak_frames_ + 1) * hop_);
    }
    window_.clear();
    for (std::int64_t i = window_begin; i < window_end; ++i) window_.push_back(samples[i]);
    std::int64_t pick_begin = window_begin;
    std::size_t pick_offset = begin_offset;
    if (in_ringing) {
      auto innovation = PredictionInnovation(window_, begin_offset, kInnovationOrder);
      const std::size_t skipped = window_.size() - innovation.size();
      if (skipped > 0 && begin_offset > skipped) {
        window_ = std::move(innovation);
        pick_begin += static_cast<std::int64_t>(skipped);
        pick_offset -= skipped;
        std::size_t top = pick_offset;
        for (std::size_t i = pick_offset; i < window_.size(); ++i) {
          if (std::fabs(window_[i]) > std::fabs(window_[top])) top = i;
        }
        peak = pick_begin + static_cast<std::int64_t>(top);
        window_.resize(std::min(window_.size(), top + 2));
      }
    }
    const auto end_offset =
        static_cast<std::size_t>(std::max<std::int64_t>(0, peak + 1 - pick_begin));
    const OnsetPick pick = PickOnset(window_, pick_offset, end_offset);
    // The rest of a sound whose candidate closed while rising cannot pick an onset before that
    // candidate's peak: when its search starts before that peak its onset is not trusted.
    const bool continuation = candidate_continues_ && search_begin <= last_peak_sample_;
    last_peak_sample_ = peak;

    Impact impact;
    const double onset_index = static_cast<double>(pick_begin) + pick.index;
    impact.onset_s = onset_index / rate_;
    impact.onset_uncertainty_s = pick.sigma_samples / rate_;
    impact.rise_db = candidate_rise_db_;
    // The residual's rise is kept scaled to the band threshold for the decisions; reported in its
    // own unit.
    impact.ringing_novelty_db =
        std::isfinite(candidate_residual_rise_db_)
            ? candidate_residual_rise_db_ * kNoveltyAtThresholdDb / options_.rise_threshold_db
            : std::numeric_limits<double>::quiet_NaN();
    impact.snr_db = snr_db;
    impact.residual_only = !band_snr_ok;
    const std::int64_t level_begin =
        std::max<std::int64_t>(raw_.begin(), std::llround(std::floor(onset_index)));
    const std::int64_t level_end = std::min(raw_.end(), level_begin + Samples(kPeakLevelMs * 1e-3));
    double peak_abs = 0;
    for (std::int64_t i = level_begin; i < level_end; ++i) {
      peak_abs = std::max(peak_abs, double{std::fabs(raw_[i])});
    }
    impact.peak_dbfs = 20.0 * std::log10(std::max(peak_abs, 1e-7));
    Merge({impact,
           candidate_peak_db_,
           std::max(candidate_rise_db_, candidate_residual_rise_db_),
           candidate_rise_db_,
           !in_ringing,
           continuation,
           {}});
  }

  // Groups rises closer than min_gap_ms to the loudest one so far: a precursor before a hit or
  // an echo after it is part of the same impact and must neither count twice nor move its
  // onset. Members only need the secondary threshold, so a main burst that rises a few dB over
  // its own precursor still takes the onset; the group counts as an impact when one member
  // rose by the full rise_threshold_db.
  void Merge(const Pending& next) {
    if (pending_ && next.impact.onset_s - pending_->impact.onset_s < options_.min_gap_ms * 1e-3) {
      const double gap_ms = (next.impact.onset_s - pending_->impact.onset_s) * 1e3;
      char text[160];
      pending_->group_rise_db = std::max(pending_->group_rise_db, next.group_rise_db);
      pending_->group_band_rise_db =
          std::max(pending_->group_band_rise_db, next.group_band_rise_db);
      // A rise that did not reach the full threshold in the bands a few ms after a hit sits in
      // that hit's tail, whose level it shares: it never takes the onset from a hit that rose by
      // the full threshold. (Counting rises of half the threshold as band rises here was
      // measured worse: alessia rimbalzi split into 3 sequences, rubberball lost 4 impacts.)
      const bool next_wins = !next.continuation && (next.band_rose == pending_->band_rose
                                                        ? next.level_db > pending_->level_db
                                                        : next.band_rose);
      if (next_wins) {
        std::snprintf(text, sizeof text,
                      "precursor %.1f ms before a louder impact (merged; --min-gap-ms %.3g)",
                      gap_ms, options_.min_gap_ms);
        pending_->others.push_back({pending_->impact.onset_s, pending_->impact.peak_dbfs, text});
        pending_->impact = next.impact;
        pending_->level_db = next.level_db;
        pending_->band_rose = next.band_rose;
      } else {
        std::snprintf(text, sizeof text,
                      "echo or secondary burst %.1f ms after a louder impact (merged; "
                      "--min-gap-ms %.3g)",
                      gap_ms, options_.min_gap_ms);
        pending_->others.push_back({next.impact.onset_s, next.impact.peak_dbfs, text});
      }
      return;
    }
    EmitPending();
    pending_ = next;
  }

  // A bounce sequence is a strong prior: the next impact is due near t_k + e dt_k. A rise of
  // only half the threshold (a quiet late bounce in a tail, or noise) is kept as tentative and
  // becomes an impact only where it continues a bounce sequence found without it, inside the
  // window where its next bounce is predicted (ExtendSequencesWithTentative, default
  // SequenceOptions): the lower threshold applies only there.
  void AdoptTentative() {
    if (tentative_.empty() || result_.impacts.empty()) return;
    result_.impacts = ExtendSequencesWithTentative(result_.impacts, tentative_);
  }

  void EmitPending() {
    if (pending_ && pending_->group_rise_db >= options_.rise_threshold_db) {
      if (pending_->group_band_rise_db < options_.rise_threshold_db) {
        pending_->impact.residual_only = true;
      }
      if (pending_->impact.residual_only) {
        // Its onset is picked on a flank inside the tail that the residual located only to
        // within its frame hop: on the synthetic free plate, in rooms and under level jitter
        // such onsets were off by a median of 133 us, p90 1.5 ms, up to 8 ms, while the picker
        // claimed ~50 us (42 % within 2 sigma). Stated as at least one hop, like the tentative
        // ones below, so the e and eta around it carry that.
        pending_->impact.onset_uncertainty_s =
            std::max(pending_->impact.onset_uncertainty_s,
                     static_cast<double>(residual_.hop_samples()) / rate_);
      }
      result_.impacts.push_back(pending_->impact);
      for (auto& other : pending_->others) result_.merged.push_back(std::move(other));
    } else if (pending_ && pending_->impact.snr_db >= options_.min_snr_db) {
      // Rose by at least half the threshold: not an impact on its own (see AdoptTentative).
      // Such a weak onset is picked on a flank the residual located only to within its frame
      // hop; on the free-plate ground truth adopted onsets were 1-1.5 ms off while the picker
      // claimed tens of us, so the stated uncertainty is at least one hop.
      pending_->impact.residual_only = true;
      pending_->impact.onset_uncertainty_s =
          std::max(pending_->impact.onset_uncertainty_s,
                   static_cast<double>(residual_.hop_samples()) / rate_);
      tentative_.push_back(pending_->impact);
    }
    pending_.reset();
  }

  int rate_;
  DetectorOptions options_;
  BandFilter filter_;
  SampleHistory<float> raw_;
  BandFilter::Sink sink_;               // Take, for the filter
  std::size_t delivered_ = 0;           // samples of the block the filter delivered last (0: none)
  std::vector<char> may_rise_;          // per frame of the block: some band may rise (see Take)
  std::vector<double> entering_;        // Take's scratch: the frames entering a band's lookback
  std::ptrdiff_t frame_in_block_ = -1;  // the frame Consume examines, -1 outside
  std::vector<float> window_;
  std::int64_t hop_;
  double frame_s_;
  std::int64_t lookback_frames_;
  std::int64_t skip_frames_;
  std::int64_t attack_frames_;
  std::int64_t peak_frames_;
  std::int64_t max_open_frames_;
  double secondary_threshold_db_;
  double secondary_rise_ratio_;  // its power ratio, less a margin (see AnyBandMayRise)
  double tail_ratio_;            // the power ratio of rise_threshold_db (see OnFrame)
  // Declared after the members MakeBands reads; the residual reads bands_[0]'s history.
  std::vector<Band> bands_;
  RingingResidual residual_;
  std::size_t residual_band_;
  double residual_noise_power_ = std::numeric_limits<double>::quiet_NaN();
  bool residual_armed_ = true;
  std::int64_t frame_fill_ = 0;
  std::int64_t frame_count_ = 0;

  bool open_ = false;
  bool candidate_continues_ = false;
  std::int64_t still_rising_until_ = -1;
  std::int64_t candidate_frame_ = 0;
  std::int64_t candidate_peak_frame_ = 0;
  std::size_t candidate_band_ = 0;
  double candidate_residual_rise_db_ = 0;
  double candidate_rise_db_ = 0;
  double candidate_peak_db_ = 0;
  std::int64_t last_peak_sample_ = -1;
  std::optional<Pending> pending_;
  std::vector<Impact> tentative_;  // rises of half the threshold, see AdoptTentative
  DetectionResult result_;
};

ImpactDetector::ImpactDetector(int sample_rate_hz, const DetectorOptions& options)
    : impl_(std::make_unique<Impl>(sample_rate_hz, options)) {}
ImpactDetector::ImpactDetector(ImpactDetector&&) noexcept = default;
ImpactDetector& ImpactDetector::operator=(ImpactDetector&&) noexcept = default;
ImpactDetector::~ImpactDetector() = default;

void ImpactDetector::Process(std::span<const float> samples) { impl_->Process(samples); }

DetectionResult ImpactDetector::Finish() { return impl_->Finish(); }

DetectionResult DetectImpacts(const Recording& recording, const DetectorOptions& options) {
  ImpactDetector detector(recording.sample_rate_hz, options);
  // Blocks of the size a file stream would use, so both paths run the same code.
  constexpr std::size_t kBlock = 1 << 16;
  const std::span<const float> all(recording.samples);
  for (std::size_t at = 0; at < all.size(); at += kBlock) {
    detector.Process(all.subspan(at, std::min(kBlock, all.size() - at)));
  }
  return detector.Finish();
}

}  // namespace bouncecal::audio
