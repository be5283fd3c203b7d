#include "sequences/periodic_sound.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "sequences/poisson_binomial.h"

namespace bouncecal::audio {
namespace {

// Each event is paired with this many events after it: enough to see a lattice whose slots are
// often empty (hum_dc as 8 kHz mu-law heard 93 of the 160 cycles of its 2.7 s), few enough that
// an hour of events stays linear.
constexpr int kNeighbours = 6;
// Intervals up to this many periods count for a period.
constexpr int kMultiples = 6;
// How far from a multiple of the period an interval of two of its events may lie: the onsets of
// hum_dc's 8 kHz mu-law hum events, paired, lie within 0.06 ms of a multiple (median) and
// 0.2 ms (90 %).
constexpr double kHalfWidthS = 3e-4;
// The densest intervals the period is sought from (each, and its whole fractions down to
// 1/kMultiples, is a candidate period).
constexpr int kPeaksTried = 4;
// A period must explain this many pairs at least, and beat the binomial tail of random intervals
// by this much over all the periods tried: a false period only costs chains whose flights all
// fall on it, but it must not come from the scatter of a drop's own intervals.
constexpr int kMinLatticePairs = 8;
constexpr double kPeriodChance = 1e-9;
// A window of intervals this dense at least offers its candidate periods: the comb over all
// multiples then judges them. A phone's AGC raising 50 Hz hum to its limiter 0.3 s before a
// drop heard 11 of 17 cycles (bench/silent_wrong_sweep.py --limiter seed 960 #176, 11 kHz as
// Opus): no window held more than 6 intervals, so no period was tried, and a chain of five hum
// events with flights of 8, 4, 2 and 1 periods read eta-bar 0.7501 +- 0.0009 against the ball's
// 0.8525, while 28 of the file's 33 intervals from 20 to 120 ms lie within 0.3 ms of a multiple
// of 20 ms (a binomial chance of 1e-37). Three is a window's fewest that is more than a
// coincidence of two of a drop's intervals (two was not tried: the comb would judge those too,
// only at the price of more periods tried); no period in 20000 drops among random sounds.
constexpr int kMinPeakPairs = 3;
// A chain's flight is on the lattice within this many robust sds of the lattice's own intervals
// about their multiples (where that is wider than kHalfWidthS): the search tries every chain, so
// it finds the few whose flights the jitter threw out of a narrower width.
constexpr double kJitterWidths = 5.0;

// ln P(X >= k) for X ~ Binomial(n, q), 0 < q < 1, by summing the terms in logarithms.
double LogBinomialTail(int n, int k, double q) {
  if (k <= 0) return 0;
  if (k > n) return -INFINITY;
  const double log_q = std::log(q), log_not_q = std::log1p(-q);
  double log_sum = -INFINITY;
  for (int i = k; i <= n; ++i) {
    const double log_term = std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) +
                            i * log_q + (n - i) * log_not_q;
    const double high = std::max(log_sum, log_term);
    log_sum = high + std::log(std::exp(log_sum - high) + std::exp(log_term - high));
    // Past the mode (k > n q where it matters) the terms fall geometrically: the rest is noise.
    if (i > n * q && log_term < log_sum - 40) break;
  }
  return log_sum;
}

// The whole number of periods nearest to `interval_s`, if it is at least one and the interval
// lies within `half_width_s` of it.
int MultipleOf(double interval_s, double period_s, double half_width_s) {
  const double multiple = std::round(interval_s / period_s);
  if (multiple < 1 || std::fabs(interval_s - multiple * period_s) > half_width_s) return 0;
  return static_cast<int>(multiple);
}

struct Comb {
  int pairs = 0;
  int on_multiples = 0;
  double log_chance = 0;
};

// How many of the sorted `intervals` in [P - w, kMultiples P + w] lie on multiples of P, and the
// binomial chance of that many for intervals at random relative to P (each within w of a
// multiple with probability 2w / P).
Comb CombAt(const std::vector<double>& intervals, double period_s) {
  const auto begin = std::lower_bound(intervals.begin(), intervals.end(), period_s - kHalfWidthS);
  const auto end = std::upper_bound(begin, intervals.end(), kMultiples * period_s + kHalfWidthS);
  Comb comb;
  for (auto it = begin; it != end; ++it) {
    ++comb.pairs;
    if (MultipleOf(*it, period_s, kHalfWidthS) > 0) ++comb.on_multiples;
  }
  comb.log_chance =
      LogBinomialTail(comb.pairs, comb.on_multiples, std::min(0.5, 2.0 * kHalfWidthS / period_s));
  return comb;
}

// The centres of the kPeaksTried densest windows of width 2 kHalfWidthS among the sorted
// intervals, no two overlapping.
std::vector<double> DensestIntervals(const std::vector<double>& intervals) {
  std::vector<double> prefix_sum(intervals.size() + 1, 0.0);
  for (std::size_t i = 0; i < intervals.size(); ++i) {
    prefix_sum[i + 1] = prefix_sum[i] + intervals[i];
  }
  std::vector<std::pair<int, double>> windows;  // count, centre
  std::size_t end = 0;
  for (std::size_t begin = 0; begin < intervals.size(); ++begin) {
    end = std::max(end, begin);
    while (end < intervals.size() && intervals[end] <= intervals[begin] + 2 * kHalfWidthS) ++end;
    const auto count = static_cast<double>(end - begin);
    windows.emplace_back(static_cast<int>(end - begin),
                         (prefix_sum[end] - prefix_sum[begin]) / count);
  }
  std::stable_sort(windows.begin(), windows.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<double> centres;
  for (const auto& window : windows) {
    if (static_cast<int>(centres.size()) == kPeaksTried || window.first < kMinPeakPairs) break;
    // Not a structured binding: clang before 16 cannot capture one in a lambda.
    const double centre = window.second;
    const bool apart = std::none_of(centres.begin(), centres.end(), [&](double other) {
      return std::fabs(other - centre) <= 2 * kHalfWidthS;
    });
    if (apart) centres.push_back(centre);
  }
  return centres;
}

}  // namespace

std::optional<PeriodicSound> FindPeriodicSound(const std::vector<Impact>& impacts,
                                               double min_period_s, double max_period_s) {
  const std::size_t n = impacts.size();
  std::vector<double> intervals;
  intervals.reserve(n * kNeighbours);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n && j <= i + kNeighbours; ++j) {
      const double interval_s = impacts[j].onset_s - impacts[i].onset_s;
      if (interval_s > kMultiples * max_period_s + kHalfWidthS) break;
      intervals.push_back(interval_s);
    }
  }
  if (static_cast<int>(intervals.size()) < kMinLatticePairs) return std::nullopt;
  std::sort(intervals.begin(), intervals.end());

  double best_period_s = 0;
  Comb best;
  int periods_tried = 0;
  for (const double centre : DensestIntervals(intervals)) {
    for (int fraction = 1; fraction <= kMultiples; ++fraction) {
      const double period_s = centre / fraction;
      if (period_s < min_period_s || period_s > max_period_s) continue;
      ++periods_tried;
      const Comb comb = CombAt(intervals, period_s);
      if (comb.log_chance < best.log_chance) {
        best = comb;
        best_period_s = period_s;
      }
    }
  }
  if (best.on_multiples < kMinLatticePairs ||
      best.log_chance + std::log(std::max(periods_tried, 1)) >= std::log(kPeriodChance)) {
    return std::nullopt;
  }

  // The period from every interval on a multiple, by least squares (interval = multiple P), and
  // the lattice's width from their scatter about it.
  std::vector<std::pair<int, double>> on_multiples;  // multiple, interval
  for (auto it = std::lower_bound(intervals.begin(), intervals.end(), best_period_s - kHalfWidthS);
       it != intervals.end() && *it <= kMultiples * best_period_s + kHalfWidthS; ++it) {
    if (const int multiple = MultipleOf(*it, best_period_s, kHalfWidthS); multiple > 0) {
      on_multiples.emplace_back(multiple, *it);
    }
  }
  double sum_product = 0, sum_squares = 0;
  for (const auto& [multiple, interval_s] : on_multiples) {
    sum_product += multiple * interval_s;
    sum_squares += static_cast<double>(multiple) * multiple;
  }
  PeriodicSound sound;
  sound.period_s = sum_product / sum_squares;
  std::vector<double> deviations;
  for (const auto& [multiple, interval_s] : on_multiples) {
    deviations.push_back(std::fabs(interval_s - multiple * sound.period_s));
  }
  const auto middle = deviations.begin() + static_cast<std::ptrdiff_t>(deviations.size() / 2);
  std::nth_element(deviations.begin(), middle, deviations.end());
  sound.half_width_s =
      std::max(kHalfWidthS, std::min(kJitterWidths * 1.4826 * *middle, 0.1 * sound.period_s));
  sound.lattice_pairs = best.on_multiples;
  sound.on_lattice.assign(n, false);
  const auto has_event_near = [&](double time_s) {
    const auto it =
        std::lower_bound(impacts.begin(), impacts.end(), time_s - sound.half_width_s,
                         [](const Impact& impact, double t) { return impact.onset_s < t; });
    return it != impacts.end() && it->onset_s <= time_s + sound.half_width_s;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (const double offset_s : {sound.period_s, 2 * sound.period_s}) {
      if (has_event_near(impacts[i].onset_s - offset_s) ||
          has_event_near(impacts[i].onset_s + offset_s)) {
        sound.on_lattice[i] = true;
      }
    }
  }
  return sound;
}

// A lattice neighbour at most this much quieter than a member makes it sound like the periodic
// source: the detector's rise threshold. A codec's sounds once a frame in a first bounce's ringing
// put the bounce on a slot of their lattice 16-30 dB under it (the codec fixture of
// bounce_sequences_test.cc); a hum's events are alike in level.
constexpr double kLatticeNeighbourQuieterDb = 10.0;

// Measured over the silent-wrong sweep's files with a periodic sound (53 of 14000, 29
// sequences): all 4 sequences that began on a lattice slot began at a sound before the drop, and
// 18 of the 374 bounces after a first member sat on a slot by chance. Seed 970 #124 (50 Hz hum at
// -27 dBFS raised to a limiter's ceiling by 25.6 dB of gain and an AGC, Opus 32k) began at a hum
// event 0.49 s before its first bounce, first ratio 0.760 against the ball's 0.65-0.69, which the
// t-test on 4 degrees of freedom (LeadingSoundsBeforeTheDrop) let through: eta-bar 0.504 against
// 0.547 (z -61), exit 0.
std::size_t LeadingEventsOfThePeriodicSound(const std::vector<Impact>& impacts,
                                            const std::vector<int>& members,
                                            const PeriodicSound& sound, std::size_t fewest_left) {
  const auto like_the_source = [&](std::size_t k) {
    const Impact& member = impacts[static_cast<std::size_t>(members[k])];
    for (const double offset_s :
         {-2 * sound.period_s, -sound.period_s, sound.period_s, 2 * sound.period_s}) {
      const double time_s = member.onset_s + offset_s;
      const auto it =
          std::lower_bound(impacts.begin(), impacts.end(), time_s - sound.half_width_s,
                           [](const Impact& impact, double t) { return impact.onset_s < t; });
      for (auto event = it; event != impacts.end() && event->onset_s <= time_s + sound.half_width_s;
           ++event) {
        if (event->peak_dbfs >= member.peak_dbfs - kLatticeNeighbourQuieterDb) return true;
      }
    }
    return false;
  };
  const auto on_lattice = [&](std::size_t k) {
    return sound.on_lattice[static_cast<std::size_t>(members[k])];
  };
  std::size_t leading = 0;
  while (leading < members.size() && like_the_source(leading)) ++leading;
  fewest_left = std::max<std::size_t>(fewest_left, 3);
  if (leading == 0 || members.size() < leading + fewest_left || on_lattice(leading) ||
      on_lattice(leading + 1)) {
    return 0;
  }
  return leading;
}

double ChanceOfFlightsOnTheLattice(const std::vector<Impact>& impacts,
                                   const std::vector<int>& members, const PeriodicSound& sound) {
  // Two counts: within the lattice's own width (half_width_s), and within each flight's stated
  // timing, which a codec can widen past the precision the events show: a sweep file's hum as AAC
  // 96k made a chain of 6 events 7 periods apart, each flight within 0.11 ms of 7 P, stated
  // +-0.1-2.2 ms each (most of it the codec's +-967 us). Each count's chance is exact for flights
  // at random relative to the lattice; the smaller one, doubled (a union bound), is the chance.
  double chance = 1;
  for (const bool stated_timing : {false, true}) {
    std::vector<double> probabilities;
    std::size_t on_multiples = 0;
    for (std::size_t k = 1; k < members.size(); ++k) {
      const Impact& from = impacts[static_cast<std::size_t>(members[k - 1])];
      const Impact& to = impacts[static_cast<std::size_t>(members[k])];
      const double half_width_s =
          stated_timing ? std::max(sound.half_width_s, 2.0 * std::hypot(from.onset_uncertainty_s,
                                                                        to.onset_uncertainty_s))
                        : sound.half_width_s;
      probabilities.push_back(std::min(1.0, 2.0 * half_width_s / sound.period_s));
      if (MultipleOf(to.onset_s - from.onset_s, sound.period_s, half_width_s) > 0) ++on_multiples;
    }
    chance = std::min(chance, PoissonBinomialTail(probabilities, on_multiples));
  }
  return std::min(1.0, 2.0 * chance);
}

}  // namespace bouncecal::audio
