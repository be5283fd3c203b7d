#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_EXTRA_EVENT_SOUND_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_EXTRA_EVENT_SOUND_H_

#include <cstdint>
#include <span>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/random_stream.h"

namespace bouncecal::audio {

// Adds the sound of a non-ball event starting at arrival_s, scaled so that its largest sample
// is about peak_amplitude (times gain): out[i] holds time (first_index + i) / sample_rate_hz.
//  - kKnock: a knuckle on a wooden table, 1.5 ms contact on low, quickly damped modes
//    (180 Hz - 1.7 kHz, 6-20 ms): clearly not the bright ringing of a ball on a plate.
//  - kThump: handling noise, a 20 ms push on a 35/70 Hz rumble (below any impact band).
//  - kStray: a 30 ms noise burst band-limited to 0.3-2.5 kHz (4th order) (like the basketball
//  file's event
//    at 2.736 s), starting at the first sample at or after arrival_s.
void AddExtraEventSound(SoundEventKind kind, double arrival_s, double peak_amplitude,
                        double sample_rate_hz, RandomStream random, std::int64_t first_index,
                        std::span<float> out);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_EXTRA_EVENT_SOUND_H_
