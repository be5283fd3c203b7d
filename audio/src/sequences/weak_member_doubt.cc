#include "sequences/weak_member_doubt.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "sequences/expected_ratio.h"

namespace bouncecal::audio {
namespace {

// The interval ratio r_k is the restitution e_k, which scatters from impact to impact by 1-5 % of
// itself on real balls (impact point, spin; the coverage suite's materials 3 and 4 %).
constexpr double kRatioScatter = 0.03;

// How far beyond its combined sigma a residual-only member may miss its prediction.
constexpr double kDoubtSigmas = 2.0;

}  // namespace

void StateDoubtOfWeakMembers(std::vector<Impact>& impacts,
                             const std::vector<BounceSequence>& sequences) {
  for (const auto& sequence : sequences) {
    const auto& members = sequence.impact_indices;
    const auto member = [&](std::size_t k) -> Impact& {
      return impacts[static_cast<std::size_t>(members[k])];
    };
    std::vector<double> ratios;
    for (std::size_t k = 3; k < members.size(); ++k) {
      const double dt0 = member(k - 2).onset_s - member(k - 3).onset_s;
      const double dt1 = member(k - 1).onset_s - member(k - 2).onset_s;
      if (dt0 <= 0 || dt1 <= 0) break;
      ratios.push_back(dt1 / dt0);
      if (!member(k).residual_only) continue;
      const double ratio = ExpectedRatio(ratios);
      const std::size_t used = std::min(ratios.size(), kRatiosPredicting);
      const double deviation_s = member(k).onset_s - (member(k - 1).onset_s + ratio * dt1);
      // The mean of n ratios misses the next by the scatter times sqrt(1 + 1 / n); the last two
      // members' timing moves the prediction by (1 + r) and r times their errors.
      const double scatter_s =
          kRatioScatter * ratio * dt1 * std::sqrt(1.0 + 1.0 / static_cast<double>(used));
      const double timing_s = std::hypot((1.0 + ratio) * member(k - 1).onset_uncertainty_s,
                                         ratio * member(k - 2).onset_uncertainty_s);
      const double explained_s =
          std::hypot(std::hypot(scatter_s, timing_s), member(k).onset_uncertainty_s);
      if (std::fabs(deviation_s) > kDoubtSigmas * explained_s) {
        member(k).onset_uncertainty_s =
            std::hypot(member(k).onset_uncertainty_s, 0.5 * std::fabs(deviation_s));
      }
    }
  }
}

}  // namespace bouncecal::audio
