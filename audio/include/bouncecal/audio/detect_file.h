#ifndef BOUNCECAL_AUDIO_DETECT_FILE_H_
#define BOUNCECAL_AUDIO_DETECT_FILE_H_

#include <filesystem>
#include <optional>
#include <vector>

#include "bouncecal/audio/codec_timing.h"
#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/load_recording.h"
#include "bouncecal/audio/response_timing.h"

namespace bouncecal::audio {

struct FileDetectionOptions {
  // 0-based channel to analyse; unset = the channel whose impacts stand furthest above its
  // noise (channels are never averaged: a 0.25 ms delay between two microphones would smear
  // every onset).
  std::optional<int> channel;
  DetectorOptions detector;
  // Frames read per block; memory use scales with it, not with the file length.
  std::size_t block_frames = 1 << 15;
};

struct FileDetection {
  RecordingInfo info;
  double duration_s = 0;
  int channel = 0;
  bool channel_chosen_automatically = false;
  // impact_to_noise_db of every channel analysed (one entry when a channel was given).
  std::vector<double> channel_impact_to_noise_db;
  // Set for a lossy file: the codec's timing error of the detector's onsets (codec_timing.h),
  // already added in quadrature to the uncertainty of every onset of `detection` that the
  // response timing did not time (all of them for G.711 and ADPCM, which it does not retime).
  std::optional<CodecTiming> codec_timing;
  // The response timing (response_timing.h): where the first lobe is unreliable
  // (FirstLobeUnreliable: a transform codec, a rate below 20 kHz) the impacts were retimed from
  // their whole response, elsewhere only where the recording determined its contact durations
  // (contact_duration_s > 0); those it aligned (own_sigma) are stated with the alignment's
  // uncertainty instead of the first lobe's.
  std::optional<ResponseTimingSummary> response_timing;
  DetectionResult detection;
};

// Streams the file once through one detector per candidate channel, which keep the samples around
// their impacts; the chosen channel's impacts are retimed from their response
// (ResponseTimingFor); for a lossy file, widens the uncertainty of every onset not timed from its
// response by the codec's measured timing error. Throws InputError for an unreadable file and
// ConfigError for a channel the file does not have or bad detector options.
FileDetection DetectImpactsInFile(const std::filesystem::path& path,
                                  const FileDetectionOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_DETECT_FILE_H_
