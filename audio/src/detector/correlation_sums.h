#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_CORRELATION_SUMS_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_CORRELATION_SUMS_H_

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace bouncecal::audio {

// The sums a normalised cross-correlation needs besides its dot products (response_timing.cc's
// Align), kept per signal so that a template aligned with many targets, or a target judged by
// several templates, has them summed once instead of once per pair. Every sum runs over the
// samples in order, one addition at a time, as the per-pair loops did: the sum of the first n
// terms is the same double for every n, so the correlations and their uncertainties are too.

// prefix[i]: the sum of x[j]^2 for j < i (prefix[0] = 0), in double.
inline std::vector<double> EnergyPrefix(std::span<const float> x) {
  std::vector<double> prefix(x.size() + 1, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    prefix[i + 1] = prefix[i] + static_cast<double>(x[i]) * x[i];
  }
  return prefix;
}

// The template's sums over its first n samples from `lead` on, for every n up to the end of x.
class TemplateSums {
 public:
  TemplateSums(std::span<const float> x, std::size_t lead) {
    const std::size_t count = x.size() > lead ? x.size() - lead : 0;
    energy_.assign(count + 1, 0.0);
    energy_squares_.assign(count + 1, 0.0);
    slope_.assign(count > 0 ? count : 1, 0.0);
    for (std::size_t t = 0; t < count; ++t) {
      const double a = x[lead + t];
      energy_[t + 1] = energy_[t] + a * a;
      energy_squares_[t + 1] = energy_squares_[t] + a * a * a * a;
      if (t + 1 < count) {
        const double da = x[lead + t + 1] - a;
        slope_[t + 1] = slope_[t] + da * da;
      }
    }
  }
  // Of x[lead, lead + n): the sum of squares, of fourth powers, and of squared first
  // differences (the n - 1 within the n samples). n at most x.size() - lead.
  double energy(std::int64_t n) const { return energy_[static_cast<std::size_t>(n)]; }
  double energy_squares(std::int64_t n) const {
    return energy_squares_[static_cast<std::size_t>(n)];
  }
  double slope(std::int64_t n) const {
    return n > 1 ? slope_[static_cast<std::size_t>(n - 1)] : 0.0;
  }

 private:
  std::vector<double> energy_;
  std::vector<double> energy_squares_;
  std::vector<double> slope_;  // [m]: the first m squared differences
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_CORRELATION_SUMS_H_
