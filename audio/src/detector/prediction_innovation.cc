#include "detector/prediction_innovation.h"

#include <algorithm>
#include <vector>

namespace bouncecal::audio {

std::vector<float> PredictionInnovation(std::span<const float> x, std::size_t fit_end, int order) {
  fit_end = std::min(fit_end, x.size());
  const auto p = static_cast<std::size_t>(std::max(order, 0));
  // At least four samples per coefficient, or the fit follows the noise.
  if (p == 0 || fit_end < 4 * p) return {x.begin(), x.end()};
  // The samples in double once (exact; every product converts them anyway).
  const std::vector<double> xd(x.begin(), x.end());
  // Sample by sample, every lag's sum advanced together: each sum still adds its products in
  // increasing i, as a loop over one lag at a time did, so the sums are the same to the bit, but
  // the p + 1 of them are independent chains that overlap, where one lag at a time waited on
  // each addition before the next (that loop and the filter's below were two thirds of this
  // function's time, and this function 2 % of analysing a WAV).
  std::vector<double> r(p + 1, 0.0);
  for (std::size_t i = 0; i < fit_end; ++i) {
    const double xi = xd[i];
    const std::size_t lags = std::min(i, p);
    for (std::size_t lag = 0; lag <= lags; ++lag) r[lag] += xi * xd[i - lag];
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
  // Four outputs at a time, each summed over j in the same order as alone (the same values):
  // four independent chains of additions instead of one.
  std::vector<float> innovation(x.size() - p);
  std::size_t i = p;
  for (; i + 4 <= x.size(); i += 4) {
    double e0 = xd[i], e1 = xd[i + 1], e2 = xd[i + 2], e3 = xd[i + 3];
    for (std::size_t j = 1; j <= p; ++j) {
      e0 += a[j] * xd[i - j];
      e1 += a[j] * xd[i + 1 - j];
      e2 += a[j] * xd[i + 2 - j];
      e3 += a[j] * xd[i + 3 - j];
    }
    innovation[i - p] = static_cast<float>(e0);
    innovation[i + 1 - p] = static_cast<float>(e1);
    innovation[i + 2 - p] = static_cast<float>(e2);
    innovation[i + 3 - p] = static_cast<float>(e3);
  }
  for (; i < x.size(); ++i) {
    double e = xd[i];
    for (std::size_t j = 1; j <= p; ++j) e += a[j] * xd[i - j];
    innovation[i - p] = static_cast<float>(e);
  }
  return innovation;
}

}  // namespace bouncecal::audio
