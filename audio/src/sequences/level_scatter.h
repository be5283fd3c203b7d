#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_LEVEL_SCATTER_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_LEVEL_SCATTER_H_

#include <vector>

namespace bouncecal::audio {

// Residual standard deviation of impact levels (dB) about their least-squares line in bounce
// number: a ball of constant restitution loses the same share of its speed at every bounce, so
// its bounces' levels fall on a line in dB, and what is left is the per-impact scatter (a spot on
// the plate, the microphone's pattern). Needs at least three levels.
double LevelScatterAboutALine(const std::vector<double>& levels);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_LEVEL_SCATTER_H_
