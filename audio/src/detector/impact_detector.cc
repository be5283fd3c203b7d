#include "bouncecal/audio/impact_detector.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "detector/band_envelopes.h"
#include "detector/candidate_tracker.h"
#include "detector/detector_frames.h"
#include "detector/event_merger.h"
#include "detector/impact_sample_keeper.h"
#include "detector/louder_rests.h"
#include "detector/novelty_sources.h"
#include "detector/onset_locator.h"
#include "detector/ringing_residual.h"
#include "detector/sample_history.h"

namespace bouncecal::audio {
namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError(what);
}

}  // namespace

void DetectorOptions::Validate(int sample_rate_hz) const {
  Require(sample_rate_hz >= 1000,
          "sample rate must be at least 1000 Hz, got " + std::to_string(sample_rate_hz));
  // Each range names its field (option_error.h): the command line shows it as its flag.
  const auto require = [](bool ok, std::vector<std::string> fields, const std::string& what) {
    if (!ok) throw OptionError(std::move(fields), what);
  };
  const double nyquist_hz = sample_rate_hz / 2.0;
  require(band_low_hz > 0 && band_low_hz < 0.9 * nyquist_hz, {"band_low_hz"},
          "band_low_hz must be in (0, " + std::to_string(0.9 * nyquist_hz) + ") Hz, got " +
              std::to_string(band_low_hz));
  require(band_high_hz <= 0 || band_high_hz > band_low_hz, {"band_high_hz", "band_low_hz"},
          "band_high_hz must be above band_low_hz (or 0 for no low-pass), got " +
              std::to_string(band_high_hz));
  require(rise_threshold_db > 0 && rise_threshold_db <= 60, {"rise_threshold_db"},
          "rise_threshold_db must be in (0, 60] dB, got " + std::to_string(rise_threshold_db));
  require(rise_lookback_ms >= 2 && rise_lookback_ms <= 200, {"rise_lookback_ms"},
          "rise_lookback_ms must be in [2, 200] ms, got " + std::to_string(rise_lookback_ms));
  require(min_snr_db >= 0 && min_snr_db <= 80, {"min_snr_db"},
          "min_snr_db must be in [0, 80] dB, got " + std::to_string(min_snr_db));
  require(min_gap_ms >= 0 && min_gap_ms <= 1000, {"min_gap_ms"},
          "min_gap_ms must be in [0, 1000] ms, got " + std::to_string(min_gap_ms));
  require(frame_ms * sample_rate_hz >= 1000.0 && frame_ms <= 5, {"frame_ms"},
          "frame_ms must be at least one sample and at most 5 ms, got " + std::to_string(frame_ms) +
              " ms");
}

class ImpactDetector::Impl {
 public:
  Impl(int sample_rate_hz, const DetectorOptions& options)
      : frames_((options.Validate(sample_rate_hz), DetectorFrames(sample_rate_hz, options))),
        use_residual_(options.ringing_residual),
        transform_coded_(options.transform_coded),
        rise_threshold_db_(options.rise_threshold_db),
        bands_(frames_, options, kSecondaryRiseFraction * options.rise_threshold_db,
               FrameRingExtra(frames_), OnsetLocator::HistorySamples(sample_rate_hz),
               std::max(OnsetLocator::HistorySamples(sample_rate_hz),
                        RingingResidual::HistorySamples(sample_rate_hz))),
        raw_(OnsetLocator::HistorySamples(sample_rate_hz) + 2 * bands_.max_latency_samples()),
        band_rise_(bands_, options.ringing_residual ? &residual_ : nullptr),
        residual_(frames_, options, bands_, FrameRing(frames_, bands_)),
        tracker_(frames_, options, bands_,
                 (residual_.window_samples() + frames_.hop - 1) / frames_.hop),
        locator_(frames_, options, bands_, residual_, raw_),
        merger_(options, static_cast<double>(residual_.hop_samples()) / sample_rate_hz,
                sample_rate_hz, bands_) {
    result_.sample_rate_hz = sample_rate_hz;
  }

  void Process(std::span<const float> samples) {
    // Feed the filter in pieces no longer than its latency so the raw history never runs more
    // than two blocks ahead of the filtered one (peak levels are read from it).
    const std::size_t piece = bands_.max_latency_samples();
    for (std::size_t at = 0; at < samples.size(); at += piece) {
      const auto part = samples.subspan(at, std::min(piece, samples.size() - at));
      if (keeper_) keeper_->Append(raw_.end(), part);
      raw_.PushBlock(part);
      Consume(bands_.Filter(part));
    }
  }

  void KeepSamplesAroundImpacts(std::int64_t before_samples, std::int64_t after_samples) {
    keeper_.emplace(before_samples, after_samples);
  }
  std::vector<SampleStretch> TakeKeptSamples() {
    return keeper_ ? keeper_->Take() : std::vector<SampleStretch>{};
  }

  DetectionResult Finish() {
    Consume(bands_.Finish());
    if (auto candidate = tracker_.Finish(bands_.frames_before_block() + frames_in_block_ - 1)) {
      Locate(*candidate);
    }
    merger_.Flush();
    result_.samples = raw_.end();
    merger_.Report(ReferenceToContactOffset(merger_.impacts()), result_);
    // A codec's file has its frame's rule instead, where the codec is known (detect_file.cc).
    if (!transform_coded_) TakeLouderRestsAsImpacts(result_, std::nullopt, rise_threshold_db_);
    std::vector<double> snr;
    for (const auto& impact : result_.impacts) snr.push_back(impact.snr_db);
    if (snr.empty()) {
      result_.impact_to_noise_db = -std::numeric_limits<double>::infinity();
    } else {
      std::nth_element(snr.begin(), snr.begin() + static_cast<std::ptrdiff_t>(snr.size() / 2),
                       snr.end());
      result_.impact_to_noise_db = snr[snr.size() / 2];
    }
    return std::move(result_);
  }

 private:
  // Frames a candidate and the windows read back from the newest, beyond the lookback.
  static std::int64_t FrameRingExtra(const DetectorFrames& frames) {
    return frames.max_open + frames.peak + frames.attack + 8;
  }
  static std::size_t FrameRing(const DetectorFrames& frames, const BandEnvelopes& bands) {
    return static_cast<std::size_t>(
        frames.lookback + FrameRingExtra(frames) +
        static_cast<std::int64_t>(bands.max_latency_samples()) / frames.hop + 1);
  }

  // Frame by frame over the samples the filter delivered. The ringing residual is computed on
  // band 0, which it reads from that band's history as far as it is advanced: each envelope
  // frame records the latest residual frame that ended in it or before (a frame completed by a
  // sample counts for that sample's envelope frame). The envelope frames are examined as they
  // complete, so the residual still holds the frames they ask about.
  void Consume(std::size_t count) {
    std::int64_t fill = bands_.fill_before_block();
    frames_in_block_ = 0;
    for (std::size_t at = 0; at < count;) {
      std::size_t run = std::min(count - at, static_cast<std::size_t>(frames_.hop - fill));
      if (use_residual_) {
        run = std::min(run, residual_.samples_to_frame());
        residual_.Advance(run);
      }
      at += run;
      fill += static_cast<std::int64_t>(run);
      if (fill == frames_.hop) {
        OnFrame(frames_in_block_++);
        fill = 0;
      }
    }
  }

  void OnFrame(std::ptrdiff_t k) {
    const std::int64_t n = bands_.frames_before_block() + k;
    residual_.EnterFrame(n, k);
    band_rise_.EnterFrame(n, k);
    tracker_.TrackPeak(n);
    // The first lookback of the file has no reference: the start of the file is not an impact.
    if (n - frames_.attack < frames_.lookback) return;
    const NoveltyRise residual = residual_.Rise(n, k, false);
    const NoveltyRise band = band_rise_.Rise(n, k, tracker_.WantsBandRise(residual));
    if (auto candidate = tracker_.Step(n, k, band, residual)) Locate(*candidate);
  }

  void Locate(const Candidate& candidate) {
    if (auto located = locator_.Locate(candidate)) {
      if (!located->change_point_found) tracker_.ClosedCandidateFoundNoOnset();
      if (keeper_) keeper_->Keep(located->onset_sample, raw_);
      merger_.Add(*located);
    }
  }

  DetectorFrames frames_;
  bool use_residual_;
  bool transform_coded_;
  double rise_threshold_db_;
  BandEnvelopes bands_;
  SampleHistory<float> raw_;
  BandRiseNovelty band_rise_;
  RingingResidualNovelty residual_;
  CandidateTracker tracker_;
  OnsetLocator locator_;
  EventMerger merger_;
  std::optional<ImpactSampleKeeper> keeper_;
  std::ptrdiff_t frames_in_block_ = 0;
  DetectionResult result_;
};

ImpactDetector::ImpactDetector(int sample_rate_hz, const DetectorOptions& options)
    : impl_(std::make_unique<Impl>(sample_rate_hz, options)) {}
ImpactDetector::ImpactDetector(ImpactDetector&&) noexcept = default;
ImpactDetector& ImpactDetector::operator=(ImpactDetector&&) noexcept = default;
ImpactDetector::~ImpactDetector() = default;

void ImpactDetector::Process(std::span<const float> samples) { impl_->Process(samples); }

DetectionResult ImpactDetector::Finish() { return impl_->Finish(); }

void ImpactDetector::KeepSamplesAroundImpacts(std::int64_t before_samples,
                                              std::int64_t after_samples) {
  impl_->KeepSamplesAroundImpacts(before_samples, after_samples);
}

std::vector<SampleStretch> ImpactDetector::TakeKeptSamples() { return impl_->TakeKeptSamples(); }

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
