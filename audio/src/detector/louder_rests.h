#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_LOUDER_RESTS_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_LOUDER_RESTS_H_

#include <optional>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// The merger keeps the onset of a candidate that closed while its sound was still rising and
// counts whatever follows within min_gap_ms as the rest of that sound, however loud
// (MergedEvent::rest_of_sound). Where the rest is far louder than the kept onset's own sound, over
// the same span from each, the kept sound was a fainter one before the impact that rose into it
// without a break, and the rest is the impact: it takes the onset, and the fainter sound becomes
// its listed precursor. Far louder: by two rise thresholds (`rise_threshold_db` each) in any file,
// by one where a transform codec's pre-echo may have joined them (within `codec_frame_s` of each
// other, CodecTiming::frame_s; nullopt for PCM). There too, every impact with a louder rest within
// one frame states half their distance in its uncertainty: either may be its onset.
void TakeLouderRestsAsImpacts(DetectionResult& detection, std::optional<double> codec_frame_s,
                              double rise_threshold_db);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_LOUDER_RESTS_H_
