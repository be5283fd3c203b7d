#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_POISSON_BINOMIAL_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_POISSON_BINOMIAL_H_

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace bouncecal::audio {

// P(at least `at_least` of independent events happen), each with its own probability (a
// Poisson-binomial tail): the distribution of the count by dynamic programming over the events.
inline double PoissonBinomialTail(const std::vector<double>& probabilities, std::size_t at_least) {
  std::vector<double> count_probability = {1.0};
  for (const double q : probabilities) {
    std::vector<double> next(count_probability.size() + 1, 0.0);
    for (std::size_t c = 0; c < count_probability.size(); ++c) {
      next[c] += count_probability[c] * (1 - q);
      next[c + 1] += count_probability[c] * q;
    }
    count_probability = std::move(next);
  }
  double tail = 0;
  for (std::size_t c = at_least; c < count_probability.size(); ++c) tail += count_probability[c];
  return std::min(1.0, tail);
}

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_POISSON_BINOMIAL_H_
