#include "level_scatter.h"

#include <cmath>
#include <cstddef>

namespace bouncecal::audio {

double LevelScatterAboutALine(const std::vector<double>& levels) {
  const double n = static_cast<double>(levels.size());
  const double x_mean = (n - 1) / 2;
  double y_mean = 0;
  for (double level : levels) y_mean += level / n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    sxx += std::pow(static_cast<double>(i) - x_mean, 2);
    sxy += (static_cast<double>(i) - x_mean) * (levels[i] - y_mean);
  }
  const double slope = sxy / sxx;
  double residual_squares = 0;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    residual_squares +=
        std::pow(levels[i] - (y_mean + slope * (static_cast<double>(i) - x_mean)), 2);
  }
  return std::sqrt(residual_squares / (n - 2));
}

}  // namespace bouncecal::audio
