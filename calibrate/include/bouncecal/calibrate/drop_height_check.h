#ifndef BOUNCECAL_CALIBRATE_DROP_HEIGHT_CHECK_H_
#define BOUNCECAL_CALIBRATE_DROP_HEIGHT_CHECK_H_

#include <optional>
#include <string>

#include "bouncecal/calibrate/restitution.h"

namespace bouncecal::calibrate {

// Does a given drop height agree with the recording? With h0 the first impact's restitution is
// e_1 = dt_1 / dt_0, dt_0 = 2 sqrt(2 h0 / g), and the next impacts' e_k = dt_k / dt_{k-1} do not
// depend on h0 at all. A missed first impact (the sequence starts at the second bounce) or a
// wrong height moves e_1 alone, by far more than a material's impact-to-impact scatter or the
// slow drift of e with impact speed: Fr4nci's Audio_1.wav with a 1.5 m height gives e_1 = 0.50
// beside e_2.. = 0.81.
//
// The test: z = (e_1 - m) / s with m the mean of the next kLaterImpacts e_k and
//   s^2 = sigma_1^2 + sd^2 (1 + 1/n) + kMaterialSpread^2,
// sigma_1 e_1's own uncertainty (timing and height), sd the sample standard deviation of those
// n later e_k (0 for n = 1: a prediction interval for one more draw), and kMaterialSpread the
// largest difference between e_1 and e_2 a consistent material shows: a few per cent of
// impact-to-impact scatter (2-5 % of e in the coverage suite's materials) plus the change of e
// with speed between two impacts (Hertz viscoelastic 1 - e ~ v^(1/5): speed falls by e, so
// 1 - e moves by ~5 %, 0.01-0.02 for e = 0.5-0.8). Inconsistent when |z| > kMaxDeviationSigma.
struct DropHeightCheck {
  static constexpr int kLaterImpacts = 5;
  static constexpr double kMaterialSpread = 0.03;
  static constexpr double kMaxDeviationSigma = 4.0;

  double drop_height_m = 0;
  double first_restitution = 0;  // e_1 from the height
  double first_restitution_uncertainty = 0;
  int later_impacts = 0;  // n
  double later_restitution_min = 0;
  double later_restitution_max = 0;
  double later_restitution_mean = 0;  // m
  double deviation_sigma = 0;         // z
  // The release height whose dt_0 makes e_1 equal to m: the height the recording implies.
  double implied_drop_height_m = 0;
  bool consistent = true;
};

// Empty without a first-impact restitution (no height, or fewer than two impacts) or without a
// later impact to compare with. `physics` must have been computed with drop_height_m.
std::optional<DropHeightCheck> CheckDropHeight(const RestitutionAnalysis& physics,
                                               double drop_height_m, double gravity_mps2);

// One sentence for an inconsistent check, naming the recording, the numbers and what to do
// (fields spelt as the library names them: drop_height_m).
std::string DescribeInconsistentDropHeight(const std::string& recording,
                                           const DropHeightCheck& check);

// The first rebound rose above the release height: e_1 > 1, which no passive ball does.
// Throws OptionError naming drop_height_m when it did.
void RefuseReboundAboveRelease(const std::string& recording, const RestitutionAnalysis& physics,
                               double drop_height_m);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_DROP_HEIGHT_CHECK_H_
