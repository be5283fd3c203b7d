#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_RATIO_SCATTER_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_RATIO_SCATTER_H_

#include <vector>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// How far a chain's interval ratios (its restitutions) lie from what one ball times: a
// restitution that drifts linearly with the bounce number (e depends on impact speed) and
// scatters from impact to impact by `relative_scatter` of itself (impact point, spin), on top
// of what the members' stated onset uncertainties give (their covariance: neighbouring ratios
// share onsets). Returns the chance that such a ball scatters its ratios as far from their
// best line (generalised least squares), the chi-square tail by the Wilson-Hilferty
// approximation; 1 where the chain has fewer than three ratios (a line fits two exactly) or its
// onsets do not increase.
double ChanceOfRatioScatter(const std::vector<Impact>& impacts, const std::vector<int>& members,
                            double relative_scatter);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_RATIO_SCATTER_H_
