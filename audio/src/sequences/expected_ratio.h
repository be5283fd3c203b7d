#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_EXPECTED_RATIO_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_EXPECTED_RATIO_H_

#include <algorithm>
#include <cstddef>
#include <vector>

namespace bouncecal::audio {

// The interval ratio expected next in a chain: the mean of its last kRatiosPredicting ratios (0
// for none). A restitution that scatters from impact to impact by sd s makes consecutive ratios
// differ by s sqrt(2) but a ratio differ from the mean of the three before it by s sqrt(4/3):
// against the last ratio alone, ratio_step_tolerance split a steel-on-anvil drop with 5 %
// scatter of e (s = 0.04) at 2.1 sd, about one flight in 30, and the knock rule then rejected
// the drop's first impacts. Three, not more: e drifts with impact speed (a ping-pong ball's
// 0.907 -> 0.95 over 60 bounces), and a mean over few recent flights follows it.
inline constexpr std::size_t kRatiosPredicting = 3;

inline double ExpectedRatio(const std::vector<double>& ratios) {
  if (ratios.empty()) return 0;
  const std::size_t count = std::min(ratios.size(), kRatiosPredicting);
  double sum = 0;
  for (std::size_t i = ratios.size() - count; i < ratios.size(); ++i) sum += ratios[i];
  return sum / static_cast<double>(count);
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_EXPECTED_RATIO_H_
