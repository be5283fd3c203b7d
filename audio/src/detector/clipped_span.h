#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_CLIPPED_SPAN_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_CLIPPED_SPAN_H_

#include <cstdint>

#include "detector/sample_history.h"

namespace bouncecal::audio {

// A sample at full scale that repeats a neighbour: the converter or the export clipped it (a
// sound's own peak does not sit on one value for two samples). Decoded integer PCM is scaled to
// [-1, 1); a float file that exceeds full scale without clipping has no repeated values there.
inline constexpr float kClippedLevel = 0.99F;

// Samples from the start of a clipped stretch to `onset`, where the stretch reaches to within
// `bridge` samples of it; 0 where none does. Unclipped runs of up to `bridge` samples inside it
// belong to it (a clipped oscillation swings back inside full scale between its half cycles).
// Looks back at most `reach` samples and never before what `raw` holds. The impact's onset can
// lie anywhere in such a stretch: clipping erased the waveform the picker times it by, and the
// picker's change point lands where the clipping lets go.
std::int64_t ClippedSamplesBefore(const SampleHistory<float>& raw, std::int64_t onset,
                                  std::int64_t bridge, std::int64_t reach);

// Samples from `onset` to the first clipped sample within `horizon` after it, where a lobe of the
// other sign reaching `min_lobe` lies in between (the onset lies on a lobe before the clipped one);
// 0 where there is none. The timing reference is a fraction of the largest sample ahead
// (kReferenceFraction, onset_picker.h): where that sample is clipped the true level is higher, and
// the reference could lie on the clipped lobe instead of the earlier one it fell on. A lobe under
// that fraction of full scale never carried it, nor does noise before the clipped lobe's own edge.
std::int64_t ClippedLobeAfter(const SampleHistory<float>& raw, std::int64_t onset,
                              std::int64_t horizon, float min_lobe);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_CLIPPED_SPAN_H_
