#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_STAGE_TEST_SUPPORT_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_STAGE_TEST_SUPPORT_H_

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "detector/band_envelopes.h"
#include "detector/detector_frames.h"
#include "detector/novelty_sources.h"
#include "detector/onset_locator.h"

namespace bouncecal::audio::testing {

// The detector's first stages on their own, for the stage tests: a signal streamed through the
// band envelopes (and the ringing residual) in pieces of `piece` samples, with `on_frame(n, k)`
// called for every completed envelope frame as ImpactDetector's driver does.
struct StageRig {
  StageRig(int rate_hz, const DetectorOptions& options = {})
      : frames(rate_hz, options),
        bands(frames, options, 0.5 * options.rise_threshold_db,
              frames.max_open + frames.peak + frames.attack + 8,
              OnsetLocator::HistorySamples(rate_hz),
              std::max(OnsetLocator::HistorySamples(rate_hz),
                       RingingResidual::HistorySamples(rate_hz))),
        residual(frames, options, bands,
                 static_cast<std::size_t>(
                     frames.lookback + frames.max_open + frames.peak + frames.attack + 8 +
                     static_cast<std::int64_t>(bands.max_latency_samples()) / frames.hop + 1)) {}

  void Run(std::span<const float> signal,
           const std::function<void(std::int64_t n, std::ptrdiff_t k)>& on_frame,
           std::size_t piece = 0) {
    if (piece == 0) piece = bands.max_latency_samples();
    piece = std::min(piece, bands.max_latency_samples());
    for (std::size_t at = 0; at < signal.size(); at += piece) {
      Consume(bands.Filter(signal.subspan(at, std::min(piece, signal.size() - at))), on_frame);
    }
    Consume(bands.Finish(), on_frame);
  }

  DetectorFrames frames;
  BandEnvelopes bands;
  RingingResidualNovelty residual;

 private:
  void Consume(std::size_t count,
               const std::function<void(std::int64_t n, std::ptrdiff_t k)>& on_frame) {
    std::int64_t fill = bands.fill_before_block();
    std::ptrdiff_t k = 0;
    for (std::size_t at = 0; at < count;) {
      std::size_t run = std::min(count - at, static_cast<std::size_t>(frames.hop - fill));
      run = std::min(run, residual.samples_to_frame());
      residual.Advance(run);
      at += run;
      fill += static_cast<std::int64_t>(run);
      if (fill == frames.hop) {
        const std::int64_t n = bands.frames_before_block() + k;
        residual.EnterFrame(n, k);
        on_frame(n, k++);
        fill = 0;
      }
    }
  }
};

}  // namespace bouncecal::audio::testing

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_STAGE_TEST_SUPPORT_H_
