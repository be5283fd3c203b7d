#include "bouncecal/audio/detect_file.h"

#include <cmath>
#include <string>
#include <utility>

#include "bouncecal/audio/response_timing.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "detector/louder_rests.h"

namespace bouncecal::audio {
namespace {

// Beyond the samples the response timing reads around a located impact, kept either side: its
// reported onset is the located one moved by the recording's reference-to-contact offset, a
// fraction of a contact time, which is at most ~1 ms for the balls this tool is for.
constexpr double kKeptMarginS = 5e-3;

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
  if (detector_options.transform_coded && result.codec_timing && result.codec_timing->frame_s) {
    TakeLouderRestsAsImpacts(result.detection, result.codec_timing->frame_s,
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
