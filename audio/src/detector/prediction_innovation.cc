#include "detector/prediction_innovation.h"

#include <algorithm>
#include <vector>

namespace bouncecal::audio {

std::vector<float> PredictionInnovation(std::span<const float> x, std::size_t fit_end, int order) {
  fit_end = std::min(fit_end, x.size());
  const auto p = static_cast<std::size_t>(std::max(order, 0));
  // At least four samples per coefficient, or the fit follows the noise.
  if (p == 0 || fit_end < 4 * p) return {x.begin(), x.end()};
  std::vector<double> r(p + 1, 0.0);
  for (std::size_t lag = 0; lag <= p; ++lag) {
    for (std::size_t i = lag; i < fit_end; ++i) r[lag] += double{x[i]} * x[i - lag];
  }
  if (r[0] <= 0) return {x.begin(), x.end()};
  // A white-noise floor of 1e-9 of the power keeps the recursion well conditioned on pure
  // tones and on digital silence.
  r[0] *= 1.0 + 1e-9;
  std::vector<double> a(p + 1, 0.0);
  std::vector<double> previous(p + 1, 0.0);
  a[0] = 1.0;
  double error = r[0];
  for (std::size_t m = 1; m <= p; ++m) {
    double acc = r[m];
    for (std::size_t j = 1; j < m; ++j) acc += a[j] * r[m - j];
    const double k = -acc / error;
    previous = a;
    for (std::size_t j = 1; j < m; ++j) a[j] = previous[j] + k * previous[m - j];
    a[m] = k;
    error *= 1.0 - k * k;
    if (error <= 0) break;
  }
  std::vector<float> innovation;
  innovation.reserve(x.size() - p);
  for (std::size_t i = p; i < x.size(); ++i) {
    double e = x[i];
    for (std::size_t j = 1; j <= p; ++j) e += a[j] * x[i - j];
    innovation.push_back(static_cast<float>(e));
  }
  return innovation;
}

}  // namespace bouncecal::audio
