#include "onset_picker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace bouncecal::audio {
namespace {

// Time (fractional index) where s * x first reaches level in [from, to], interpolated linearly
// between samples; negative when it never does.
double Crossing(std::span<const float> x, std::size_t from, std::size_t to, double sign,
                double level) {
  for (std::size_t i = std::max<std::size_t>(from, 1); i <= to; ++i) {
    const double b = sign * x[i];
    if (b >= level) {
      const double a = sign * x[i - 1];
      if (a >= level) return static_cast<double>(i - 1);
      return static_cast<double>(i - 1) + (level - a) / (b - a);
    }
  }
  return -1.0;
}

}  // namespace

OnsetPick PickOnset(std::span<const float> x, std::size_t search_begin, std::size_t search_end) {
  const std::size_t n = x.size();
  OnsetPick pick;
  if (n < 8) {
    pick.index = static_cast<double>(std::min(search_begin, n));
    pick.sigma_samples = 1.0;
    return pick;
  }
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + double{x[i]} * x[i];
  // Floor on the variances: digital silence before an onset must not give log(0).
  const double tiny = 1e-20 + 1e-12 * prefix[n] / static_cast<double>(n);
  const std::size_t first = std::max<std::size_t>(search_begin, 2);
  const std::size_t last = std::min(search_end, n - 2);
  std::vector<double> aic;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = first;
  for (std::size_t k = first; k < last; ++k) {
    const double before = prefix[k] / static_cast<double>(k) + tiny;
    const double after = (prefix[n] - prefix[k]) / static_cast<double>(n - k) + tiny;
    const double value =
        static_cast<double>(k) * std::log(before) + static_cast<double>(n - k) * std::log(after);
    aic.push_back(value);
    if (value < best) {
      best = value;
      best_k = k;
    }
  }
  if (aic.empty()) {
    pick.index = static_cast<double>(std::min(search_begin, n - 1));
    pick.sigma_samples = 1.0;
    return pick;
  }
  // One-sigma profile-likelihood interval of the change point.
  std::size_t lo = best_k - first;
  while (lo > 0 && aic[lo - 1] <= best + 1.0) --lo;
  std::size_t hi = best_k - first;
  while (hi + 1 < aic.size() && aic[hi + 1] <= best + 1.0) ++hi;
  const double half_width = 0.5 * static_cast<double>(hi - lo);
  const double quantisation = 1.0 / std::sqrt(12.0);

  // x[best_k] is the first sample of the impact; contact began in (best_k - 1, best_k].
  pick.index = static_cast<double>(best_k) - 0.5;
  pick.sigma_samples = std::hypot(half_width, quantisation);

  // Sub-sample refinement: follow the first half-cycle of the impact to its extremum and
  // extrapolate the line through its 20 % and 60 % crossings back to zero. The radiated
  // pressure of a plate mode driven by a contact force that grows from zero rises linearly at
  // first, so a line through the lower part of the edge meets zero at the start of contact.
  const double noise_rms = std::sqrt(prefix[best_k] / static_cast<double>(best_k));
  std::size_t lead = best_k;
  for (std::size_t i = best_k; i < std::min(best_k + 3, n); ++i) {
    if (std::fabs(x[i]) > std::fabs(x[lead])) lead = i;
  }
  const double sign = x[lead] >= 0 ? 1.0 : -1.0;
  std::size_t top = best_k;
  while (sign * x[top] <= 0 && top < lead) ++top;
  while (top + 1 < n && sign * x[top + 1] >= sign * x[top]) ++top;
  const double amplitude = sign * x[top];
  if (amplitude < 5.0 * noise_rms || top <= best_k) return pick;
  const std::size_t from = best_k >= 3 ? best_k - 3 : 0;
  // Keep both levels clear of the noise, or the crossings are noise-driven.
  const double low = std::max(0.2 * amplitude, 2.0 * noise_rms);
  const double high = std::max(0.6 * amplitude, low + 2.0 * noise_rms);
  if (high >= amplitude) return pick;
  const double t_low = Crossing(x, from, top, sign, low);
  const double t_high = Crossing(x, from, top, sign, high);
  if (t_low < 0 || t_high <= t_low) return pick;
  const double slope = (high - low) / (t_high - t_low);
  const double onset = t_low - low / slope;
  // Trust the extrapolation only where it agrees with the AIC change point.
  if (onset < static_cast<double>(best_k) - 4.0 || onset > static_cast<double>(best_k) + 1.0) {
    return pick;
  }
  pick.index = onset;
  // Noise moves each crossing by about noise_rms / slope.
  const double timing = std::sqrt(2.0) * noise_rms / slope;
  pick.sigma_samples = std::hypot(quantisation, timing, 0.5 * half_width);
  return pick;
}

}  // namespace bouncecal::audio
