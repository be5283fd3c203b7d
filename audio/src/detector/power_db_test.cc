#include "detector/power_db.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace bouncecal::audio {
namespace {

// Against std::log10 over the whole range the detector sees (digital silence at 1e-14 up to a
// clipped full-scale square, and subnormals for safety), on a dense log-spaced grid: 1e-9 dB
// is the stated accuracy (a series to s^11 with |s| <= 0.172 leaves ~1e-10 relative).
TEST(PowerToDb, AgreesWithLog10ToANanodecibel) {
  double worst = 0;
  for (double exponent = -320; exponent <= 10; exponent += 0.0137) {
    const double power = std::pow(10.0, exponent);
    if (!(power > 0)) continue;
    worst = std::max(worst, std::fabs(PowerToDb(power) - 10.0 * std::log10(power)));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_DOUBLE_EQ(PowerToDb(1.0), 0.0);
  const double tiniest = std::numeric_limits<double>::denorm_min();
  EXPECT_NEAR(PowerToDb(tiniest), 10.0 * std::log10(tiniest), 1e-9);
}

// Monotonic across the mantissa fold at sqrt(2) (checked ulp by ulp right at the fold and in
// 1e-7 steps around it), so the conversion invents no rise.
TEST(PowerToDb, IsMonotonicAcrossTheMantissaFold) {
  const double fold = std::sqrt(2.0);
  double power = fold;
  for (int i = 0; i < 1000; ++i) power = std::nextafter(power, 0.0);
  double previous = PowerToDb(power);
  for (int i = 0; i < 2000; ++i) {
    power = std::nextafter(power, 2.0);
    const double db = PowerToDb(power);
    EXPECT_GE(db, previous) << power;
    previous = db;
  }
  previous = PowerToDb(1.3);
  for (power = 1.3; power < 1.5; power += 1e-7) {
    const double db = PowerToDb(power);
    EXPECT_GE(db, previous) << power;
    previous = db;
  }
}

}  // namespace
}  // namespace bouncecal::audio
