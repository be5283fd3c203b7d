#include "sequences/level_scatter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace bouncecal::audio {
namespace {

// Levels on a line in bounce number (a ball of constant restitution, no per-impact scatter)
// scatter by nothing, whatever the line's slope and offset. 1e-12 dB: rounding of sums of ~10.
TEST(LevelScatter, LevelsOnALineScatterByNothing) {
  std::vector<double> levels;
  for (int i = 0; i < 9; ++i) levels.push_back(-3.0 - 1.7 * i);
  EXPECT_NEAR(LevelScatterAboutALine(levels), 0.0, 1e-12);
}

// A residual pattern (1, -2, 1) d is orthogonal to a constant and to a slope, so the fit leaves
// it whole: 6 d^2 of squares over one degree of freedom (three levels less the line's two).
TEST(LevelScatter, WhatTheLineDoesNotExplainIsTheScatterPerDegreeOfFreedom) {
  const double d = 1.5;
  const std::vector<double> levels = {-4.0 + d, -6.0 - 2 * d, -8.0 + d};
  EXPECT_NEAR(LevelScatterAboutALine(levels), std::sqrt(6.0) * d, 1e-12);
}

}  // namespace
}  // namespace bouncecal::audio
