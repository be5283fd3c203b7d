#include "bouncecal/calibrate/drop_height_check.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "bouncecal/option_error.h"

namespace bouncecal::calibrate {

std::optional<DropHeightCheck> CheckDropHeight(const RestitutionAnalysis& physics,
                                               double drop_height_m, double gravity_mps2) {
  if (physics.impact_index.empty() || physics.impact_index.front() != 0) return std::nullopt;
  const auto available = static_cast<int>(physics.restitution.size()) - 1;
  const int later = std::min(DropHeightCheck::kLaterImpacts, available);
  if (later < 1) return std::nullopt;

  DropHeightCheck check;
  check.drop_height_m = drop_height_m;
  check.first_restitution = physics.restitution.front();
  check.first_restitution_uncertainty = physics.restitution_uncertainty.front();
  check.later_impacts = later;
  const auto begin = physics.restitution.begin() + 1;
  const auto end = begin + later;
  check.later_restitution_min = *std::min_element(begin, end);
  check.later_restitution_max = *std::max_element(begin, end);
  double mean = 0;
  for (auto e = begin; e != end; ++e) mean += *e / later;
  double squares = 0;
  for (auto e = begin; e != end; ++e) squares += (*e - mean) * (*e - mean);
  const double sd = later > 1 ? std::sqrt(squares / (later - 1)) : 0.0;
  check.later_restitution_mean = mean;
  const double sigma =
      std::sqrt(std::pow(check.first_restitution_uncertainty, 2) + sd * sd * (1.0 + 1.0 / later) +
                std::pow(DropHeightCheck::kMaterialSpread, 2));
  check.deviation_sigma = (check.first_restitution - mean) / sigma;
  check.consistent = std::abs(check.deviation_sigma) <= DropHeightCheck::kMaxDeviationSigma;
  // e_1 = dt_1 / dt_0 = m  =>  dt_0 = dt_1 / m, h0 = g dt_0^2 / 8.
  const double incoming = physics.intervals_s.front() / mean;
  check.implied_drop_height_m = gravity_mps2 * incoming * incoming / 8.0;
  return check;
}

std::string DescribeInconsistentDropHeight(const std::string& recording,
                                           const DropHeightCheck& check) {
  return fmt::format(
      "{}: e_1 = {:.4f} +- {:.4f} from drop_height_m = {:.4g} m lies {:.1f} sigma from the next "
      "{} impacts' e = {:.4f}-{:.4f} (mean {:.4f}); the first impact was probably missed or the "
      "height is wrong (these bounces imply a release from {:.3g} m): check the first impacts "
      "with analyze, correct drop_height_m, or leave it out to fit from the first measured "
      "bounce",
      recording, check.first_restitution, check.first_restitution_uncertainty, check.drop_height_m,
      std::abs(check.deviation_sigma), check.later_impacts, check.later_restitution_min,
      check.later_restitution_max, check.later_restitution_mean, check.implied_drop_height_m);
}

void RefuseReboundAboveRelease(const std::string& recording, const RestitutionAnalysis& physics,
                               double drop_height_m) {
  if (physics.bounce_height_m.empty()) return;
  const double first_rebound_m = physics.bounce_height_m.front();
  if (first_rebound_m <= drop_height_m) return;
  throw OptionError(
      {"drop_height_m"},
      fmt::format("recording {}: the first rebound rose to {:.4g} m (a {:.4g} s flight), higher "
                  "than the drop height {:.4g} m; give the height the ball was released from, "
                  "or omit drop_height_m to fit from the measured bounces",
                  recording, first_rebound_m, physics.intervals_s.front(), drop_height_m));
}

}  // namespace bouncecal::calibrate
