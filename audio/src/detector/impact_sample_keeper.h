#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_IMPACT_SAMPLE_KEEPER_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_IMPACT_SAMPLE_KEEPER_H_

#include <cstdint>
#include <span>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "detector/sample_history.h"

namespace bouncecal::audio {

// Keeps the raw samples around every located impact while the recording streams past, so the
// stage that times impacts from their whole response (response_timing.h) runs on the first
// pass: reading a 10-minute AAC file a second time (decoding it again) cost a fifth of its
// analysis time (analyze_bench: 1076 -> 850 ms without it). Memory is (before + after) samples
// per impact, not the file's length.
class ImpactSampleKeeper {
 public:
  ImpactSampleKeeper(std::int64_t before_samples, std::int64_t after_samples);

  // An impact located at onset_sample (a fractional index): its stretch starts with what the
  // history still holds and grows with every later Append. Stretches that overlap are one.
  void Keep(double onset_sample, const SampleHistory<float>& history);
  // The next samples of the stream; block_begin is the index of its first.
  void Append(std::int64_t block_begin, std::span<const float> block);
  std::vector<SampleStretch> Take();

 private:
  std::int64_t before_;
  std::int64_t after_;
  std::vector<SampleStretch> stretches_;
  // One past the last sample the newest stretch wants: only the newest still grows, because
  // impacts are located in the order of the stream.
  std::int64_t wanted_end_ = 0;
  std::int64_t CollectedEnd() const;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_IMPACT_SAMPLE_KEEPER_H_
