#include "sequences/merged_alternatives.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace bouncecal::audio {
namespace {

// ln of an interval ratio scatters by the restitution's relative scatter, which the sequence's
// other ratios show: twice their median absolute deviation about the line, 1.35 times the sd it
// estimates (1.4826 MAD), since that sd from 6-12 ratios is uncertain by about 40 % and an
// underestimate is what lets a precursor take a bounce's onset; never below 1 %, since a few
// ratios can agree by chance.
constexpr double kMinLnRatioScatter = 0.01;
constexpr double kScatterOverMad = 2.0;
// How much better (in the sum of squared misfits over the scatter squared) the merged sound must
// continue the ratios: a likelihood ratio of e^6 between the two onsets. With 3 % scatter of e a
// precursor 3 ms before a bounce, or an echo 3 ms after it, then takes its onset in 1.5 % of drops
// (the ball's own scatter at that bounce is what the other sound smooths;
// merged_alternatives_test.cc).
constexpr double kRequiredImprovement = 12.0;
// A merged sound more than this much quieter than the member over the same span (two of the
// detector's 10 dB rise thresholds, a hundredfold in power) is no alternative: a precursor rings
// into its bounce and keeps their candidate together only while the bounce rises less than one
// threshold above it (docs/detector.md), and levels differ from bounce to bounce by a few dB, so
// a sound that faint is not what another member could have been timed on. With 3 % scatter of e
// the ratios of a 7-bounce drop alone preferred a sound 38 dB under the second bounce, 10.9 ms
// before it (the coverage suite's copper_e065_j3_s3113).
constexpr double kMaxQuieterDb = 20.0;
// Ratios on each side of the member that the reference line is fitted on.
constexpr int kReferenceReach = 6;

struct RatioFit {
  double misfit = 0;   // sum of squared misfits in ln of the ratios member k moves
  double scatter = 0;  // robust sd of the other ratios about the line
};

// The upper median (values is reordered).
double Median(std::vector<double>& values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Sum over the ratios that member k's onset moves of their squared misfit in ln against the line
// through the others within kReferenceReach; nullopt without 3 such others.
std::optional<RatioFit> Misfit(const std::vector<double>& times, int k) {
  const int n = static_cast<int>(times.size());
  // ln_ratio[j] = ln((t[j+1] - t[j]) / (t[j] - t[j-1])), j = 1 .. n-2.
  const auto ln_ratio = [&](int j) {
    return std::log((times[j + 1] - times[j]) / (times[j] - times[j - 1]));
  };
  std::vector<int> reference;
  for (int j = std::max(1, k - 1 - kReferenceReach); j <= std::min(n - 2, k + 1 + kReferenceReach);
       ++j) {
    if (j < k - 1 || j > k + 1) reference.push_back(j);
  }
  if (reference.size() < 3) return std::nullopt;
  // Theil-Sen: the median of the pairwise slopes, then of the intercepts. A chain's last ratios
  // (chatter, in-ringing members) can be far off, and a least-squares line would tilt to them.
  std::vector<double> slopes;
  for (std::size_t a = 0; a < reference.size(); ++a) {
    for (std::size_t b = a + 1; b < reference.size(); ++b) {
      slopes.push_back((ln_ratio(reference[b]) - ln_ratio(reference[a])) /
                       (reference[b] - reference[a]));
    }
  }
  const double slope = Median(slopes);
  std::vector<double> intercepts;
  for (int j : reference) intercepts.push_back(ln_ratio(j) - slope * j);
  const double intercept = Median(intercepts);
  RatioFit fit;
  for (int j = std::max(1, k - 1); j <= std::min(n - 2, k + 1); ++j) {
    const double d = ln_ratio(j) - (intercept + slope * j);
    fit.misfit += d * d;
  }
  std::vector<double> deviations;
  for (int j : reference) deviations.push_back(std::fabs(ln_ratio(j) - (intercept + slope * j)));
  fit.scatter = std::max(kMinLnRatioScatter, kScatterOverMad * Median(deviations));
  return fit;
}

// The merged sound becomes the member and the onset the merger kept becomes the merged sound, so
// what the recording reports as set aside is what was.
void SwapWithTheMember(MergedEvent& event, double kept_s) {
  const double taken_s = event.time_s;
  char text[200];
  std::snprintf(text, sizeof text,
                "the merger's onset for the impact now at %.5f s, %.1f ms %s it: the sound "
                "there, which the merger had set aside, continues the bounce sequence's interval "
                "ratios better (merged)",
                taken_s, std::fabs(taken_s - kept_s) * 1e3, kept_s < taken_s ? "before" : "after");
  event.time_s = kept_s;
  event.winner_s = taken_s;
  event.reason = text;
  event.rest_of_sound = false;
  event.level_difference_db = -event.level_difference_db;
}

}  // namespace

void TakeMergedOnsetsThatFitTheSequence(std::vector<Impact>& impacts,
                                        std::vector<MergedEvent>& merged,
                                        const std::vector<BounceSequence>& sequences) {
  for (const auto& sequence : sequences) {
    const auto& members = sequence.impact_indices;
    std::vector<double> times;
    for (int index : members) times.push_back(impacts[static_cast<std::size_t>(index)].onset_s);
    for (std::size_t k = 1; k + 1 < members.size(); ++k) {
      Impact& member = impacts[static_cast<std::size_t>(members[k])];
      // An aligned onset is its own evidence, even where the alignment left it where the detector
      // put it: the recording's constant between response and onset is the weighted median over
      // its impacts, so the best-timed impact's aligned onset is its detector onset to the bit.
      // Taken for one the response timing never saw, such a bounce lost its onset to a sound 6.5
      // ms before it (silent_wrong_sweep.py seed 9 #27, MP3 64k: eta-bar 0.3304 +- 0.0023
      // against the exact 0.3455).
      if (member.timed_from_response) continue;
      std::optional<RatioFit> now;
      double best_misfit = 0;
      MergedEvent* best_event = nullptr;
      for (MergedEvent& event : merged) {
        if (event.winner_s != member.onset_s || event.time_s == member.onset_s) continue;
        if (event.level_difference_db > kMaxQuieterDb) continue;
        if (!(event.time_s > times[k - 1] && event.time_s < times[k + 1])) continue;
        if (!now) {
          now = Misfit(times, static_cast<int>(k));
          if (!now) break;
          best_misfit = now->misfit;
        }
        std::vector<double> moved = times;
        moved[k] = event.time_s;
        const auto alternative = Misfit(moved, static_cast<int>(k));
        if (alternative && alternative->misfit < best_misfit) {
          best_misfit = alternative->misfit;
          best_event = &event;
        }
      }
      if (best_event &&
          (now->misfit - best_misfit) / (now->scatter * now->scatter) > kRequiredImprovement) {
        const double taken_s = best_event->time_s;
        SwapWithTheMember(*best_event, member.onset_s);
        member.onset_s = taken_s;
        times[k] = taken_s;
      }
    }
  }
}

}  // namespace bouncecal::audio
