#ifndef BOUNCECAL_AUDIO_SRC_ONSET_PICKER_H_
#define BOUNCECAL_AUDIO_SRC_ONSET_PICKER_H_

#include <cstddef>
#include <span>

namespace bouncecal::audio {

struct OnsetPick {
  double index = 0;          // fractional sample index into the window
  double sigma_samples = 0;  // one-sigma uncertainty
};

// Start of contact inside a window of band-passed samples that holds noise (or the tail of an
// earlier impact) followed by the rising edge of one impact, up to its first peak.
//
// The change point is the minimum of the Akaike information criterion of a two-segment model
// (Maeda 1985; Sleeman & van Eck, PEPI 113, 1999), searched in [search_begin, search_end). The
// AIC is -2 log L up to constants, so the points within 1 of its minimum form a one-sigma
// profile-likelihood interval: its half-width, with the quantisation floor 1/sqrt(12) sample,
// is the uncertainty. The change point is then refined below one sample by extrapolating the
// leading edge of the first rise back to the noise level.
OnsetPick PickOnset(std::span<const float> window, std::size_t search_begin,
                    std::size_t search_end);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_ONSET_PICKER_H_
