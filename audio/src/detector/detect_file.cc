#include "bouncecal/audio/detect_file.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "bouncecal/audio/response_timing.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"

namespace bouncecal::audio {
namespace {

// Beyond the samples the response timing reads around a located impact, kept either side: its
// reported onset is the located one moved by the recording's reference-to-contact offset, a
// fraction of a contact time, which is at most ~1 ms for the balls this tool is for.
constexpr double kKeptMarginS = 5e-3;

// A transform codec spreads the quantisation noise of a loud attack over the block before it
// (pre-echo, up to a frame ahead), and that noise can rise into the attack without a break: the
// merger then keeps the onset where the rise began and counts the attack as the rest of its
// sound, whatever its level. Where such a rest follows within one frame, either onset may be the
// impact's: half their distance goes into its uncertainty in quadrature, as the response timing
// does where it and the detector disagree (a later alignment, if any, still decides).
// Where the rest is louder by the full rise threshold over the same span from each onset, it is
// the onset: a sound that much louder after a fainter one is a new hit (the merger's own test for
// a precursor, event_merger.cc), which the codec's noise merely joined to the sound before it.
// basketball.wav as MP3 128k: a -27 dBFS sound 8.1 ms before the first bounce, kept apart in the
// WAV (the bounce's first 8 ms 18.7 dB louder), rose into the bounce in the copy and took its
// onset: eta-bar 0.3000 against the WAV's 0.2937, stated +- 0.0003 (13 sigmas) before the
// widening and +- 0.0051 with it. Taking the louder rest: 0.2938 +- 0.0032. alessia rimbalzi's
// Palla-audio, whose 7th bounce has a sound 8 ms and 22-25 dB before it, moved 0.0002-0.0005
// closer to the WAV in three of its four copies.
void ResolvePreEchoMerges(DetectionResult& detection, double frame_s, double rise_threshold_db) {
  for (MergedEvent& merged : detection.merged) {
    const double gap_s = merged.time_s - merged.winner_s;
    if (!merged.rest_of_sound || !(merged.level_difference_db < 0) || !(gap_s > 0) ||
        gap_s > frame_s) {
      continue;
    }
    const bool rest_is_the_hit = -merged.level_difference_db >= rise_threshold_db;
    for (Impact& impact : detection.impacts) {
      if (impact.onset_s != merged.winner_s) continue;
      impact.onset_uncertainty_s = std::hypot(impact.onset_uncertainty_s, 0.5 * gap_s);
      if (rest_is_the_hit) {
        impact.onset_s = merged.time_s;
        std::swap(impact.peak_dbfs, merged.peak_dbfs);
      }
    }
    if (rest_is_the_hit) {
      char reason[256];
      std::snprintf(reason, sizeof reason,
                    "precursor %.1f ms before the impact at %.5f s, %.1f dB quieter; a lossy "
                    "codec's pre-echo joined them into one rise (merged; half their distance is "
                    "in the impact's uncertainty)",
                    gap_s * 1e3, merged.time_s, -merged.level_difference_db);
      // The precursors and echoes merged into the kept sound now belong to the impact where it
      // moved. Another rest of that sound keeps its old winner and so takes no part: its level
      // was measured against the kept sound, not against the rest that became the impact.
      for (MergedEvent& other : detection.merged) {
        if (&other != &merged && !other.rest_of_sound && other.winner_s == merged.winner_s) {
          other.winner_s = merged.time_s;
        }
      }
      std::swap(merged.time_s, merged.winner_s);
      merged.reason = reason;
      merged.rest_of_sound = false;
      merged.level_difference_db = -merged.level_difference_db;
    }
  }
}

}  // namespace

FileDetection DetectImpactsInFile(const std::filesystem::path& path,
                                  const FileDetectionOptions& options) {
  RecordingReader reader(path);
  const RecordingInfo& info = reader.info();
  if (options.channel && (*options.channel < 0 || *options.channel >= info.channel_count)) {
    throw OptionError({"channel"}, "`channel` " + std::to_string(*options.channel) +
                                       " does not exist in " + path.string() +
                                       ", which has channels 0.." +
                                       std::to_string(info.channel_count - 1));
  }
  if (options.block_frames == 0) throw ConfigError("block size must be at least one frame");
  std::vector<int> channels;
  if (options.channel) {
    channels.push_back(*options.channel);
  } else {
    for (int c = 0; c < info.channel_count; ++c) channels.push_back(c);
  }
  // Every channel keeps its impacts' samples for the response timing, since which one is
  // analysed is known only at the end. The margin covers the step from where an impact was
  // located to its reported onset (the timing reference's lead over the start of contact,
  // ReferenceToContactOffset).
  const auto margin = static_cast<std::int64_t>(std::ceil(kKeptMarginS * info.sample_rate_hz));
  DetectorOptions detector_options = options.detector;
  detector_options.transform_coded = detector_options.transform_coded || TransformCodec(info);
  std::vector<ImpactDetector> detectors;
  for (std::size_t i = 0; i < channels.size(); ++i) {
    detectors.emplace_back(info.sample_rate_hz, detector_options);
    detectors.back().KeepSamplesAroundImpacts(
        ResponseTimer::SamplesBeforeOnset(info.sample_rate_hz) + margin,
        ResponseTimer::SamplesAfterOnset(info.sample_rate_hz) + margin);
  }
  std::vector<std::vector<float>> block;
  while (reader.ReadBlock(block, options.block_frames)) {
    for (std::size_t i = 0; i < channels.size(); ++i) {
      detectors[i].Process(block[static_cast<std::size_t>(channels[i])]);
    }
  }
  FileDetection result;
  result.info = info;
  result.duration_s = static_cast<double>(reader.frames_read()) / info.sample_rate_hz;
  result.channel_chosen_automatically = !options.channel && channels.size() > 1;
  std::size_t best = 0;
  std::vector<DetectionResult> detections;
  for (std::size_t i = 0; i < channels.size(); ++i) {
    detections.push_back(detectors[i].Finish());
    result.channel_impact_to_noise_db.push_back(detections.back().impact_to_noise_db);
    // Strictly better only, so ties keep the lowest channel and the choice is deterministic.
    if (detections[i].impact_to_noise_db > detections[best].impact_to_noise_db) best = i;
  }
  result.channel = channels[best];
  result.detection = std::move(detections[best]);
  // Here, not in a caller, so every path from a file to onsets (analyze, the calibration input,
  // AnalyzeBounces' other callers) carries it once, and the sequence search's tolerances see it.
  result.codec_timing = CodecTimingOf(info);
  const double codec_sigma_s = result.codec_timing ? result.codec_timing->onset_uncertainty_s : 0;
  if (result.codec_timing && result.codec_timing->frame_s) {
    ResolvePreEchoMerges(result.detection, *result.codec_timing->frame_s,
                         options.detector.rise_threshold_db);
  }
  ResponseTimer timer(result.detection, ResponseTimingFor(info));
  {
    // Released before the timer's own working copies are made (Apply).
    const std::vector<SampleStretch> stretches = detectors[best].TakeKeptSamples();
    for (const SampleStretch& stretch : stretches) timer.Process(stretch);
  }
  detectors.clear();
  result.response_timing = timer.Apply(result.detection, codec_sigma_s);
  return result;
}

}  // namespace bouncecal::audio
