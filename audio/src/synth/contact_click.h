#ifndef BOUNCECAL_AUDIO_SRC_SYNTH_CONTACT_CLICK_H_
#define BOUNCECAL_AUDIO_SRC_SYNTH_CONTACT_CLICK_H_

#include <cstdint>
#include <span>

namespace bouncecal::audio {

// The acceleration-noise pulse of one ball impact (see SynthesisOptions::click_gain): a
// half-sine peak * sin(pi (t - arrival_s) / contact_s) on [arrival_s, arrival_s + contact_s),
// the shape of the contact force.
struct ContactClick {
  double arrival_s = 0.0;
  double peak = 0.0;
  double contact_s = 1e-4;
};

// Adds every click, sampled as it is (no band limiting: at an audio rate it aliases), to out;
// out[i] holds time (first_index + i) / sample_rate_hz.
void AddContactClicks(std::span<const ContactClick> clicks, double sample_rate_hz,
                      std::int64_t first_index, std::span<float> out);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SYNTH_CONTACT_CLICK_H_
