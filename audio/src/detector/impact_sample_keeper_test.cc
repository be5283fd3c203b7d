#include "detector/impact_sample_keeper.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "bouncecal/audio/response_timing.h"
#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {
namespace {

std::vector<float> Ramp(std::size_t count) {
  std::vector<float> samples(count);
  for (std::size_t i = 0; i < count; ++i) samples[i] = static_cast<float>(i);
  return samples;
}

// Streams `stream` through a history and the keeper in blocks of `block`, keeping an impact
// wherever `onsets` says once the history has passed onset + located_after samples.
std::vector<SampleStretch> KeepAround(const std::vector<float>& stream,
                                      const std::vector<double>& onsets, std::size_t block,
                                      std::int64_t located_after) {
  SampleHistory<float> history(256);
  ImpactSampleKeeper keeper(10, 20);
  std::size_t next = 0;
  for (std::size_t at = 0; at < stream.size(); at += block) {
    const std::span<const float> part(stream.data() + at, std::min(block, stream.size() - at));
    keeper.Append(history.end(), part);
    history.PushBlock(part);
    while (next < onsets.size() && static_cast<double>(history.end()) >=
                                       onsets[next] + static_cast<double>(located_after)) {
      keeper.Keep(onsets[next++], history);
    }
  }
  return keeper.Take();
}

// Every kept sample is the stream's own, at its own index, and overlapping impacts share one
// stretch: what the response timing reads from the stretches is what it reads from the stream.
TEST(ImpactSampleKeeper, KeepsTheStreamsSamplesAroundEachImpactOverlapsAsOneStretch) {
  const std::vector<float> stream = Ramp(1000);
  for (std::size_t block : {1u, 7u, 64u, 200u}) {
    // 100 and 115 overlap ([90, 121) and [105, 136)); 500 stands alone; 990 runs past the end.
    const auto stretches = KeepAround(stream, {100.4, 115.0, 500.0, 990.0}, block, 5);
    ASSERT_EQ(stretches.size(), 3u) << block;
    EXPECT_EQ(stretches[0].begin, 90);
    EXPECT_EQ(stretches[0].samples.size(), 136u - 90u);
    EXPECT_EQ(stretches[1].begin, 490);
    EXPECT_EQ(stretches[1].samples.size(), 31u);
    EXPECT_EQ(stretches[2].begin, 980);
    EXPECT_EQ(stretches[2].samples.size(), 20u);  // the stream ends at 1000
    for (const auto& stretch : stretches) {
      for (std::size_t i = 0; i < stretch.samples.size(); ++i) {
        ASSERT_EQ(stretch.samples[i], static_cast<float>(stretch.begin) + static_cast<float>(i));
      }
    }
  }
}

// An impact located later than one before it (the merger sees them out of order by a few
// samples) still gets its samples from the history, in the same stretch.
TEST(ImpactSampleKeeper, AnImpactLocatedOutOfOrderExtendsTheStretchBackwards) {
  const std::vector<float> stream = Ramp(400);
  const auto stretches = KeepAround(stream, {200.0, 195.0}, 16, 40);
  ASSERT_EQ(stretches.size(), 1u);
  EXPECT_EQ(stretches[0].begin, 185);
  EXPECT_EQ(stretches[0].samples.size(), 221u - 185u);
  for (std::size_t i = 0; i < stretches[0].samples.size(); ++i) {
    ASSERT_EQ(stretches[0].samples[i], 185.0f + static_cast<float>(i));
  }
}

// The detector keeps what the response timing reads, so retiming from its stretches gives
// bit for bit the onsets that retiming from the whole recording gives, whatever the blocks.
TEST(ImpactSampleKeeper, RetimingFromTheKeptStretchesEqualsRetimingFromTheWholeRecording) {
  for (int seed = 1; seed <= 4; ++seed) {
    SynthesisOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.drop.drop_height_m = 0.3;
    options.drop.restitution.constant = 0.75;
    NoiseOptions noise;
    noise.snr_db = 35;
    options.noise = noise;
    const auto recording = SynthesizeBounces(options);
    const Recording& channel = recording.channels[0];

    DetectionResult whole = DetectImpacts(channel);
    ASSERT_GE(whole.impacts.size(), 6u) << seed;
    const auto whole_summary = RetimeFromResponses(whole, channel.samples);
    ASSERT_GT(whole_summary.aligned, 0) << seed;

    for (std::size_t block : {std::size_t{333}, std::size_t{1} << 15}) {
      ImpactDetector detector(channel.sample_rate_hz);
      const int rate = channel.sample_rate_hz;
      detector.KeepSamplesAroundImpacts(ResponseTimer::SamplesBeforeOnset(rate) + rate / 200,
                                        ResponseTimer::SamplesAfterOnset(rate) + rate / 200);
      const std::span<const float> all(channel.samples);
      for (std::size_t at = 0; at < all.size(); at += block) {
        detector.Process(all.subspan(at, std::min(block, all.size() - at)));
      }
      DetectionResult kept = detector.Finish();
      ResponseTimer timer(kept);
      for (const SampleStretch& stretch : detector.TakeKeptSamples()) timer.Process(stretch);
      const auto kept_summary = timer.Apply(kept, 0.0);
      EXPECT_EQ(kept_summary.aligned, whole_summary.aligned) << seed;
      ASSERT_EQ(kept.impacts.size(), whole.impacts.size()) << seed;
      for (std::size_t i = 0; i < kept.impacts.size(); ++i) {
        EXPECT_EQ(kept.impacts[i].onset_s, whole.impacts[i].onset_s) << seed << " " << i;
        EXPECT_EQ(kept.impacts[i].onset_uncertainty_s, whole.impacts[i].onset_uncertainty_s);
      }
    }
  }
}

}  // namespace
}  // namespace bouncecal::audio
