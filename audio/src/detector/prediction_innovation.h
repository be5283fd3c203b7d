#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_PREDICTION_INNOVATION_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_PREDICTION_INNOVATION_H_

#include <cstddef>
#include <span>
#include <vector>

namespace bouncecal::audio {

// Removes the ringing of earlier impacts from a window before its onset is picked. A sum of
// exponentially damped modes is an autoregressive process (order 2 per mode), so a linear
// predictor fitted on the samples before the new impact [0, fit_end) predicts the ringing
// almost exactly, and the prediction error (innovation) over the whole window holds only
// noise and what is new: the impact. Fitted by the autocorrelation method and the
// Levinson-Durbin recursion (Makhoul, Proc. IEEE 63(4), 1975), which is always stable.
// Returns the innovation of x[order..] (the first `order` samples have no past to be predicted
// from and are left out: the result is `order` samples shorter than x). With fewer than
// 4 * order samples to fit on, returns x unchanged: check the length.
std::vector<float> PredictionInnovation(std::span<const float> x, std::size_t fit_end, int order);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_PREDICTION_INNOVATION_H_
