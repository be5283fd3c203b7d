#include "detector/onset_picker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace bouncecal::audio {
namespace {

// A sample belongs to the impact's first lobe when it stands this many noise sigmas out: 4
// sigma leaves a Gaussian noise sample one chance in 16,000 of being taken for the lobe.
constexpr double kLobeNoiseSigmas = 4.0;
// With no noise at all (digital silence before the impact), float rounding is the floor.
constexpr double kLobeFloorFraction = 1e-3;
// The first lobe's edge follows the power law up to about this fraction of the lobe's
// extremum; above, the lobe bends over (see FitLeadingEdge in the header).
constexpr double kEdgeCeiling = 0.6;
// A lobe whose first sample above the noise is already at kShortEdgeLevel of its extremum,
// while the noise threshold is below kShortEdgeNoiseFraction of it, rose within about one
// sample: a t^3 edge that reaches half its extremum in one step from below 2 % is shorter than
// two samples, so its start lies within 1.5 samples of that first sample whatever its power.
constexpr double kShortEdgeLevel = 0.5;
constexpr double kShortEdgeNoiseFraction = 0.02;
// The spread of the reference crossing between impacts of one drop beyond the noise's part, as a
// fraction of the samples from the crossing to its lobe's top: their contact durations and the
// mix of modes they excite differ, so a fixed fraction of the peak is reached a little earlier
// or later on the edge, or on the next lobe. Set so that 95 % of the errors (less each drop's
// constant offset) lie within two sigmas on synthetic drops (bench/detector_accuracy_bench).
constexpr double kReferenceShapeFraction = 0.5;
// The same as a fraction of the samples from the start of contact to the crossing.
constexpr double kReferenceLeadFraction = 0.5;
// The same, in samples, where no lobe top is measured (a reference from the fitted edge).
constexpr double kReferenceShapeSamples = 0.9;
// A lobe next to the one the reference was taken on is a rival when it comes this close to the
// level: the earlier one within this fraction under it, or the crossing lobe's top within the
// inverse over it. Then a little more noise, tail or another mix of modes moves the crossing a
// whole lobe (a ping-pong ball's weak late bounces on a table were timed one lobe late, +110 to
// +170 us, at a stated 35-58 us; bench/detector_accuracy_bench "ping-pong on table"), and half
// the distance to the rival's crossing widens the reference's uncertainty.
constexpr double kRivalLobeFraction = 0.5;
// How far the fitted edge may reach the reference level from where the samples reach it before
// the fit is taken for another lobe's (see PickOnset).
constexpr double kReferenceConsistencySamples = 1.0;
// Samples of noise before the first lobe that enter the fit: they tell the fit where the edge
// was still zero.
constexpr std::size_t kNoiseSamplesInFit = 4;
// Prior on the power p (see the header) and its range.
constexpr double kPowerPrior = 3.0;
constexpr double kPowerPriorSigma = 1.0;
constexpr double kMinPower = 1.0;
constexpr double kMaxPower = 4.0;
// Model error of the power law, as a fraction of each sample.
constexpr double kModelErrorFraction = 0.05;
// Grid of the fit: t0 in steps of 1/8 sample and p in steps of 1/4, then a refinement around
// the best point in steps of 1/64 sample and 1/20. The cost is smooth on these scales (the
// edge spans several samples), so the grid finds its minimum to the refinement step without
// the risk of a local search stopping in a side minimum, and it is deterministic.
constexpr double kCoarseStep = 1.0 / 8;
constexpr double kCoarsePowerStep = 0.25;
constexpr double kFineStep = 1.0 / 64;
constexpr double kFinePowerStep = 0.05;
// rms distance from one end of a span to a point spread evenly over it, per unit of its length.
constexpr double kHiddenSpanToSigma = 0.57735026918962576;  // 1 / sqrt(3)

// Weighted least-squares fit of y ~ a u^p (a >= 0) for fixed t0 and several p at once, with
// u_i = i - t0 and weights 1 / variance_i.
class EdgeModel {
 public:
  EdgeModel(std::vector<double> y, std::vector<double> variance, double first_index)
      : y_(std::move(y)), first_(first_index) {
    for (std::size_t i = 0; i < y_.size(); ++i) {
      weight_.push_back(1.0 / variance[i]);
      wyy_ += weight_[i] * y_[i] * y_[i];
    }
  }

  // Cost (chi-square plus the prior on p) of the best amplitude for t0 and each p of
  // p0, p0 + dp, ..., p0 + (count - 1) dp; returns the lowest and its p.
  double Best(double t0, double p0, double dp, int count, double& best_p) {
    power_.resize(y_.size());
    step_.resize(y_.size());
    for (std::size_t i = 0; i < y_.size(); ++i) {
      const double u = first_ + static_cast<double>(i) - t0;
      power_[i] = u > 0 ? std::pow(u, p0) : 0.0;
      step_[i] = u > 0 ? std::pow(u, dp) : 0.0;
    }
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < count; ++j) {
      const double p = p0 + j * dp;
      double wyu = 0, wuu = 0;
      for (std::size_t i = 0; i < y_.size(); ++i) {
        wyu += weight_[i] * y_[i] * power_[i];
        wuu += weight_[i] * power_[i] * power_[i];
        power_[i] *= step_[i];  // u^(p + dp) for the next j, without a pow per sample
      }
      const double chi_square = wuu > 0 && wyu > 0 ? wyy_ - wyu * wyu / wuu : wyy_;
      const double prior = (p - kPowerPrior) / kPowerPriorSigma;
      const double cost = chi_square + prior * prior;
      if (cost < best) {
        best = cost;
        best_p = p;
      }
    }
    return best;
  }

  // Least-squares amplitude a of y ~ a u^p at t0 and p (0 when the edge would fall).
  double Amplitude(double t0, double p) const {
    double wyu = 0, wuu = 0;
    for (std::size_t i = 0; i < y_.size(); ++i) {
      const double u = first_ + static_cast<double>(i) - t0;
      const double up = u > 0 ? std::pow(u, p) : 0.0;
      wyu += weight_[i] * y_[i] * up;
      wuu += weight_[i] * up * up;
    }
    return wuu > 0 && wyu > 0 ? wyu / wuu : 0.0;
  }

 private:
  std::vector<double> y_;
  std::vector<double> weight_;
  double first_;
  double wyy_ = 0;
  std::vector<double> power_;
  std::vector<double> step_;
};

}  // namespace

// The edge a (i - t0)^p stays below kLobeNoiseSigmas noise sigmas, where by the picker's own
// lobe rule a sample cannot be told from noise, for tau = (k sigma_n / a)^(1/p) samples after
// t0. k = 4 rather than, say, 2, because that is the rule that decided where the lobe begins.
double HiddenEdgeSamples(double amplitude, double power, double noise_rms) {
  if (!(amplitude > 0) || !(noise_rms > 0) || !(power > 0)) return 0.0;
  return std::pow(kLobeNoiseSigmas * noise_rms / amplitude, 1.0 / power);
}

std::optional<OnsetPick> FitLeadingEdge(std::span<const float> x, std::size_t change_point,
                                        double noise_rms) {
  const std::size_t n = x.size();
  if (change_point >= n) return std::nullopt;
  // The first lobe: the first sample near the change point that stands out of the noise. Its
  // sign is the lobe's; the largest sample may belong to a later, opposite lobe.
  const std::size_t scan_begin = change_point >= 2 ? change_point - 2 : 0;
  const std::size_t scan_end = std::min(n, change_point + 3);
  double loudest = 0;
  for (std::size_t i = scan_begin; i < scan_end; ++i) {
    loudest = std::max(loudest, double{std::fabs(x[i])});
  }
  const double threshold = std::max(kLobeNoiseSigmas * noise_rms, kLobeFloorFraction * loudest);
  std::size_t first = scan_begin;
  while (first < scan_end && std::fabs(x[first]) < threshold) ++first;
  if (first == scan_end || threshold <= 0) return std::nullopt;
  const double sign = x[first] >= 0 ? 1.0 : -1.0;
  std::size_t top = first;
  while (top + 1 < n && sign * x[top + 1] >= sign * x[top]) ++top;
  const double amplitude = sign * x[top];
  // An edge that jumps from clean noise to half the lobe within one sample (an impulsive
  // click, or a low sample rate) has one sample on its rise at most: its power cannot be told,
  // and extrapolating it with the prior's p = 3 would put an impulsive (p = 1) onset a sample
  // early. Contact began in the sample interval before the lobe, and nothing tells where.
  // Where the noise is higher the edge's lower part may just be hidden in it, and the fit with
  // its prior on p extrapolates it.
  if (sign * x[first] >= kShortEdgeLevel * amplitude &&
      threshold <= kShortEdgeNoiseFraction * amplitude) {
    return OnsetPick{static_cast<double>(first) - 0.5, 1.0 / std::sqrt(12.0)};
  }
  std::size_t last = first;
  while (last < top && sign * x[last + 1] < kEdgeCeiling * amplitude) ++last;
  // A lone sample above the noise fits any onset before it: take the next one in as well.
  std::size_t significant = 0;
  for (std::size_t i = first; i <= last; ++i) significant += sign * x[i] >= threshold ? 1 : 0;
  if (significant < 2 && last < top) ++last;

  const std::size_t from = first >= kNoiseSamplesInFit ? first - kNoiseSamplesInFit : 0;
  std::vector<double> y;
  for (std::size_t i = from; i <= last; ++i) y.push_back(sign * x[i]);
  // Each sample's variance: the noise, plus the power law's own error, relative to the sample
  // (so the samples before the edge keep the noise's full weight and pin the start down), plus
  // a float-rounding floor for digital silence.
  std::vector<double> variance;
  for (double v : y) {
    const double model_error = kModelErrorFraction * v;
    const double rounding = kLobeFloorFraction * kLobeFloorFraction * amplitude;
    variance.push_back(noise_rms * noise_rms + model_error * model_error + rounding * rounding);
  }
  EdgeModel model(std::move(y), std::move(variance), static_cast<double>(from));

  // Contact starts before the lobe's first sample (already above the noise) and, for an edge
  // that stands out of the noise within a few samples, at most kNoiseSamplesInFit before it.
  const double t_begin = static_cast<double>(from);
  const double t_end = static_cast<double>(first);
  const int coarse_powers =
      static_cast<int>(std::lround((kMaxPower - kMinPower) / kCoarsePowerStep)) + 1;
  std::vector<double> profile;  // lowest cost over p at each coarse t0
  double best_cost = std::numeric_limits<double>::infinity();
  double best_t0 = t_begin;
  double best_p = kPowerPrior;
  for (double t0 = t_begin; t0 < t_end; t0 += kCoarseStep) {
    double p = 0;
    profile.push_back(model.Best(t0, kMinPower, kCoarsePowerStep, coarse_powers, p));
    if (profile.back() < best_cost) {
      best_cost = profile.back();
      best_t0 = t0;
      best_p = p;
    }
  }
  const std::size_t coarse_at =
      static_cast<std::size_t>(std::lround((best_t0 - t_begin) / kCoarseStep));
  const double p_low = std::max(kMinPower, best_p - kCoarsePowerStep);
  const double p_high = std::min(kMaxPower, best_p + kCoarsePowerStep);
  const int fine_powers = static_cast<int>(std::lround((p_high - p_low) / kFinePowerStep)) + 1;
  const double centre = best_t0;
  for (double t0 = std::max(t_begin, centre - kCoarseStep);
       t0 <= std::min(t_end - kFineStep, centre + kCoarseStep); t0 += kFineStep) {
    double p = 0;
    const double cost = model.Best(t0, p_low, kFinePowerStep, fine_powers, p);
    if (cost < best_cost) {
      best_cost = cost;
      best_t0 = t0;
      best_p = p;
    }
  }

  // Profile-likelihood interval: where the coarse profile stays within 1 of the minimum,
  // with the crossings interpolated between grid points. An interval that reaches the end of
  // the search range is cut there: contact cannot start outside it.
  const double level = best_cost + 1.0;
  auto crossing = [&](std::size_t inside, std::size_t outside) {
    const double a = profile[inside] - level;
    const double b = profile[outside] - level;
    const double f = a < 0 && b > a ? -a / (b - a) : 0.5;
    return t_begin +
           kCoarseStep * (static_cast<double>(inside) +
                          f * (static_cast<double>(outside) - static_cast<double>(inside)));
  };
  std::size_t lo = coarse_at;
  while (lo > 0 && profile[lo - 1] <= level) --lo;
  std::size_t hi = coarse_at;
  while (hi + 1 < profile.size() && profile[hi + 1] <= level) ++hi;
  const double interval_begin = lo > 0 ? crossing(lo, lo - 1) : t_begin;
  const double interval_end = hi + 1 < profile.size() ? crossing(hi, hi + 1) : t_end;
  const double profile_sigma = std::max(0.5 * (interval_end - interval_begin), kFineStep);
  OnsetPick pick;
  pick.index = best_t0;
  // Neither the change point nor the fit sees inside the hidden span: contact may have begun
  // anywhere in it. It cannot reach past the first visible sample. The fit's origin sits at the
  // span's late end (the noise samples in the fit pull it there; the errors the profile misses
  // are late ones), so the rms distance to an onset spread evenly over the span is tau/sqrt(3).
  const double hidden_samples =
      std::min(HiddenEdgeSamples(model.Amplitude(best_t0, best_p), best_p, noise_rms),
               static_cast<double>(first) - best_t0);
  pick.sigma_samples = std::hypot(profile_sigma, kHiddenSpanToSigma * hidden_samples);
  pick.edge_amplitude = model.Amplitude(best_t0, best_p);
  pick.edge_power = best_p;
  return pick;
}

namespace {

// The level at which the edge through sample i is timed: kReferenceFraction of the largest sample
// within kReferenceHorizonSamples from i on, so an impact is timed on its own first lobe even
// where a later lobe of its ringing is larger.
double LargestMagnitude(std::span<const float> x, std::size_t begin, std::size_t end) {
  double largest = 0;
  for (std::size_t i = begin; i < end; ++i) largest = std::max(largest, double{std::fabs(x[i])});
  return largest;
}

double ReferenceLevelAt(std::span<const float> x, std::size_t i, std::size_t peak_end) {
  return kReferenceFraction *
         LargestMagnitude(x, i, std::min(peak_end, i + kReferenceHorizonSamples));
}

// Whether the impact's own level (a fraction of the window's largest sample) is reached within
// kReferenceHorizonSamples of sample f: a soft impact's body follows its first lobe at once, while
// a lobe further ahead of it is another sound (a precursor click 2-10 ms before the impact).
bool ImpactLevelFollows(std::span<const float> x, std::size_t f, std::size_t peak_end,
                        double impact_level) {
  const std::size_t end = std::min(peak_end, f + kReferenceHorizonSamples);
  for (std::size_t i = f; i < end; ++i) {
    if (std::fabs(x[i]) >= impact_level) return true;
  }
  return false;
}

// Samples from the reference crossing at f (on the lobe whose top is `top`) to where a rival lobe
// would have been crossed (see kRivalLobeFraction); 0 where neither neighbour is a rival.
double RivalLobeDistance(std::span<const float> x, std::size_t from, std::size_t f, std::size_t top,
                         std::size_t peak_end, double level, double sign) {
  double distance = 0;
  // The earlier lobe: the largest excursion of the other sign within the horizon before the
  // crossing lobe began.
  std::size_t start = f;
  while (start > from && sign * x[start - 1] > 0) --start;
  const std::size_t earliest =
      f >= from + kReferenceHorizonSamples ? f - kReferenceHorizonSamples : from;
  double earlier = 0;
  std::size_t earlier_at = start;
  for (std::size_t i = start; i-- > earliest;) {
    if (sign * x[i] > 0) break;  // the lobe before it, of the crossing lobe's sign
    if (std::fabs(x[i]) > earlier) {
      earlier = std::fabs(x[i]);
      earlier_at = i;
    }
  }
  if (earlier >= kRivalLobeFraction * level) {
    // Its crossing would lie on its edge: back to where it rose through half its top.
    std::size_t edge = earlier_at;
    while (edge > earliest && sign * x[edge - 1] < 0 && std::fabs(x[edge - 1]) >= 0.5 * earlier) {
      --edge;
    }
    distance = static_cast<double>(f - edge);
  }
  // The later lobe: where the crossing lobe barely clears the level, the next lobe's edge.
  if (sign * x[top] * kRivalLobeFraction < level) {
    std::size_t next = top;
    while (next + 1 < peak_end && sign * x[next + 1] > 0) ++next;
    while (next + 1 < peak_end && std::fabs(x[next + 1]) < level) ++next;
    if (next + 1 < peak_end) distance = std::max(distance, static_cast<double>(next + 1 - f));
  }
  return distance;
}

}  // namespace

std::optional<OnsetPick> ReferenceCrossing(std::span<const float> x, std::size_t from,
                                           std::size_t peak_end, double noise_rms) {
  peak_end = std::min(peak_end, x.size());
  if (from >= peak_end) return std::nullopt;
  const double impact_level = kReferenceFraction * LargestMagnitude(x, from, peak_end);
  const double floor = kLobeNoiseSigmas * noise_rms;
  if (!(impact_level > 0) || impact_level < floor) return std::nullopt;
  std::size_t f = from;
  double level = 0;
  for (; f < peak_end; ++f) {
    const double magnitude = std::fabs(x[f]);
    level = ReferenceLevelAt(x, f, peak_end);
    if (level >= floor && magnitude >= level && ImpactLevelFollows(x, f, peak_end, impact_level)) {
      break;
    }
    if (magnitude >= impact_level) {
      level = impact_level;
      break;
    }
  }
  if (f == peak_end) return std::nullopt;  // only with NaN samples
  OnsetPick pick;
  pick.reference_level = level;
  if (f == 0) {
    pick.reference_index = 0;
    pick.reference_sigma_samples = 1.0;
  } else {
    // Along the lobe that crosses: the sample before may still be on the other side of zero.
    const double sign = x[f] >= 0 ? 1.0 : -1.0;
    const double before = sign * x[f - 1];
    const double after = sign * x[f];
    const double slope = after - before;
    const double fraction = std::clamp((level - before) / slope, 0.0, 1.0);
    pick.reference_index = static_cast<double>(f - 1) + fraction;
    // The shape term scales with how long the lobe takes from the crossing to its top: a slow
    // (long-contact) edge spreads the same fraction of the peak over more samples.
    std::size_t top = f;
    while (top + 1 < peak_end && sign * x[top + 1] >= sign * x[top]) ++top;
    const double to_top = std::max(1.0, static_cast<double>(top) - pick.reference_index);
    pick.reference_sigma_samples = std::hypot(
        noise_rms / slope, std::max(kReferenceShapeSamples, kReferenceShapeFraction * to_top));
    pick.reference_sigma_samples =
        std::hypot(pick.reference_sigma_samples,
                   0.5 * RivalLobeDistance(x, from, f, top, peak_end, level, sign));
  }
  pick.index = pick.reference_index;
  pick.sigma_samples = pick.reference_sigma_samples;
  return pick;
}

namespace {

// Samples from `from` to the first one that stands kLobeNoiseSigmas out of the noise and is
// followed within kReferenceHorizonSamples by twice that (the impact under way, not a noise
// sample); 0 where none does.
double ClearOfNoiseAfter(std::span<const float> x, std::size_t from, std::size_t peak_end,
                         double noise_rms) {
  const double floor = kLobeNoiseSigmas * noise_rms;
  peak_end = std::min(peak_end, x.size());
  for (std::size_t f = from; f < peak_end; ++f) {
    if (std::fabs(x[f]) >= floor && ImpactLevelFollows(x, f, peak_end, 2.0 * floor)) {
      return static_cast<double>(f - from);
    }
  }
  return 0.0;
}

// What PickOnset needs besides the start of contact to place the timing reference.
struct ContactStart {
  OnsetPick pick;
  std::size_t change_point = 0;
  double start_aic_excess = std::numeric_limits<double>::infinity();
  double noise_rms = 0;
  bool edge_fitted = false;
};

ContactStart PickContactStart(std::span<const float> x, std::size_t search_begin,
                              std::size_t search_end) {
  ContactStart result;
  OnsetPick& pick = result.pick;
  const std::size_t n = x.size();
  if (n < 8) {
    pick.index = static_cast<double>(std::min(search_begin, n));
    pick.sigma_samples = 1.0;
    return result;
  }
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + double{x[i]} * x[i];
  // Floor on the variances: digital silence before an onset must not give log(0).
  const double tiny = 1e-20 + 1e-12 * prefix[n] / static_cast<double>(n);
  const std::size_t first = std::max<std::size_t>(search_begin, 2);
  const std::size_t last = std::min(search_end, n - 2);
  std::vector<double> aic;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = first;
  for (std::size_t k = first; k < last; ++k) {
    const double before = prefix[k] / static_cast<double>(k) + tiny;
    const double after = (prefix[n] - prefix[k]) / static_cast<double>(n - k) + tiny;
    const double value =
        static_cast<double>(k) * std::log(before) + static_cast<double>(n - k) * std::log(after);
    aic.push_back(value);
    if (value < best) {
      best = value;
      best_k = k;
    }
  }
  if (aic.empty()) {
    pick.index = static_cast<double>(std::min(search_begin, n - 1));
    pick.sigma_samples = 1.0;
    return result;
  }
  result.start_aic_excess = aic.front() - best;
  // One-sigma profile-likelihood interval of the change point.
  std::size_t lo = best_k - first;
  while (lo > 0 && aic[lo - 1] <= best + 1.0) --lo;
  std::size_t hi = best_k - first;
  while (hi + 1 < aic.size() && aic[hi + 1] <= best + 1.0) ++hi;
  const double half_width = 0.5 * static_cast<double>(hi - lo);
  const double quantisation = 1.0 / std::sqrt(12.0);

  // x[best_k] is the first sample of the impact; contact began in (best_k - 1, best_k].
  pick.index = static_cast<double>(best_k) - 0.5;
  pick.sigma_samples = std::hypot(half_width, quantisation);

  // The noise before the impact; the two samples before the change point may already hold
  // the faint start of the edge, so they are left out where there is enough noise without them.
  const std::size_t noise_end = best_k >= 10 ? best_k - 2 : best_k;
  const double noise_rms = std::sqrt(prefix[noise_end] / static_cast<double>(noise_end));
  result.change_point = best_k;
  result.noise_rms = noise_rms;
  const auto edge = FitLeadingEdge(x, best_k, noise_rms);
  // Trust the fit only where it agrees with the change point.
  if (!edge || edge->index < static_cast<double>(best_k) - 4.0 ||
      edge->index > static_cast<double>(best_k) + 1.0) {
    // No fitted edge: an edge with the prior's power through the largest sample after the
    // change point, visible from the change point on, stands for it. It reaches k sigma_n at a
    // fraction r = (k sigma_n / peak)^(1/p) of its rise, so the span hidden before the change
    // point is r (peak - change point) / (1 - r); it is cut at the kNoiseSamplesInFit samples
    // the fit would search, beyond which the change point would have seen the impact.
    std::size_t top = best_k;
    for (std::size_t i = best_k; i < std::min(n, std::max(search_end, best_k + 1)); ++i) {
      if (std::fabs(x[i]) > std::fabs(x[top])) top = i;
    }
    const double cap = static_cast<double>(kNoiseSamplesInFit);
    const double r =
        std::fabs(x[top]) > 0
            ? std::pow(kLobeNoiseSigmas * noise_rms / std::fabs(x[top]), 1.0 / kPowerPrior)
            : 1.0;
    const double hidden_samples =
        r < 1 ? std::min(cap, r * static_cast<double>(top - best_k) / (1 - r)) : cap;
    pick.sigma_samples = std::hypot(pick.sigma_samples, kHiddenSpanToSigma * hidden_samples);
    return result;
  }
  pick = *edge;
  // The change point's spread stands for what the fit cannot see: whether an earlier, fainter
  // lobe hid in the noise.
  pick.sigma_samples = std::hypot(edge->sigma_samples, 0.5 * half_width);
  result.edge_fitted = true;
  return result;
}

}  // namespace

OnsetPick PickOnset(std::span<const float> x, std::size_t search_begin, std::size_t search_end) {
  ContactStart start = PickContactStart(x, search_begin, search_end);
  OnsetPick pick = start.pick;
  pick.start_aic_excess = start.start_aic_excess;
  if (x.size() < 8) return pick;
  // The reference is searched from the search window's start: where the window ends at a later,
  // larger lobe, the change point may fall on that lobe's build-up rather than on the first.
  const std::size_t from =
      std::min(search_begin, start.change_point >= 2 ? start.change_point - 2 : 0);
  const std::size_t peak_end = std::min(x.size(), std::max(search_end, from) + 1);
  if (const auto reference = ReferenceCrossing(x, from, peak_end, start.noise_rms)) {
    pick.reference_index = reference->reference_index;
    pick.reference_sigma_samples = reference->reference_sigma_samples;
    // The fitted edge must reach the reference level where the samples do; where it does not
    // (the change point fell on noise or a tail before the impact, or on a later lobe), the edge
    // is fitted again where the reference puts it, against the noise before that.
    const auto crossing = static_cast<std::size_t>(std::ceil(pick.reference_index));
    pick.reference_level = reference->reference_level;
    const double fitted_reference =
        start.edge_fitted && pick.edge_amplitude > 0
            ? pick.index +
                  std::pow(pick.reference_level / pick.edge_amplitude, 1.0 / pick.edge_power)
            : std::numeric_limits<double>::quiet_NaN();
    if (!(std::fabs(fitted_reference - pick.reference_index) <= kReferenceConsistencySamples) &&
        crossing >= 10) {
      double power = 0;
      for (std::size_t i = 0; i < crossing - 2; ++i) power += double{x[i]} * x[i];
      const double noise_rms = std::sqrt(power / static_cast<double>(crossing - 2));
      const auto edge = FitLeadingEdge(x, crossing, noise_rms);
      if (edge && edge->index >= static_cast<double>(crossing) - 4.0 &&
          edge->index <= pick.reference_index) {
        pick.index = edge->index;
        pick.sigma_samples = edge->sigma_samples;
        pick.edge_amplitude = edge->edge_amplitude;
        pick.edge_power = edge->edge_power;
      } else {
        pick.edge_amplitude = std::numeric_limits<double>::quiet_NaN();
      }
    }
    // A slow edge (a long contact) reaches the level after more samples, over which a fixed
    // fraction of the peak moves more with the impact's shape.
    pick.reference_sigma_samples = std::max(
        pick.reference_sigma_samples, kReferenceLeadFraction * (pick.reference_index - pick.index));
    return pick;
  }
  // The level lies in the noise: where the fitted edge reaches it.
  if (start.edge_fitted && pick.edge_amplitude > 0) {
    // The level ReferenceCrossing would have used at the edge's origin.
    const auto origin = static_cast<std::size_t>(
        std::clamp(std::ceil(pick.index), 0.0, static_cast<double>(peak_end - 1)));
    const double impact_level = kReferenceFraction * LargestMagnitude(x, from, peak_end);
    pick.reference_level = ImpactLevelFollows(x, origin, peak_end, impact_level)
                               ? ReferenceLevelAt(x, origin, peak_end)
                               : impact_level;
    const double rise = std::pow(pick.reference_level / pick.edge_amplitude, 1.0 / pick.edge_power);
    pick.reference_index = pick.index + rise;
    pick.reference_sigma_samples = std::hypot(pick.sigma_samples, kReferenceShapeSamples);
    // The edge was fitted on the lobe the change point found; an earlier lobe that comes as close
    // to the level may have been the impact's first, under the tail (see kRivalLobeFraction).
    const auto f = static_cast<std::size_t>(
        std::clamp(std::ceil(pick.reference_index), 0.0, static_cast<double>(peak_end - 1)));
    const double sign = x[f] >= 0 ? 1.0 : -1.0;
    std::size_t top = f;
    while (top + 1 < peak_end && sign * x[top + 1] >= sign * x[top]) ++top;
    pick.reference_sigma_samples =
        std::hypot(pick.reference_sigma_samples,
                   0.5 * RivalLobeDistance(x, from, f, top, peak_end, pick.reference_level, sign));
  } else if (!start.edge_fitted) {
    // Neither a reference nor an edge: the onset is the change point, which in a tail can sit on
    // the tail's own excursion before the impact (a soft ball's click on a plate's hum, 0.2 ms
    // early at 4 stated sigmas in the detector suite), while timing where the impact clears the
    // noise instead fires a lobe late on a weak impact (tried: 4 of 20 suite files worse). The
    // onset lies between the two: half their distance widens it.
    pick.sigma_samples =
        std::hypot(pick.sigma_samples,
                   0.5 * ClearOfNoiseAfter(x, start.change_point, peak_end, start.noise_rms));
  }
  return pick;
}

OnsetPick PickOnsetInInnovation(std::span<const float> innovation, std::size_t search_begin,
                                std::size_t largest, std::size_t burst_samples,
                                double min_start_aic_excess) {
  const std::size_t edge_end = std::min(innovation.size(), largest + 2);
  const std::size_t search_end = std::min(edge_end, largest + 1);
  const OnsetPick pick = PickOnset(innovation.first(edge_end), search_begin, search_end);
  if (edge_end >= innovation.size() ||
      pick.index < static_cast<double>(largest) - kDegenerateChangePointSamples) {
    return pick;
  }
  const std::size_t burst_end = std::min(innovation.size(), edge_end + burst_samples);
  const OnsetPick burst = PickOnset(innovation.first(burst_end), search_begin, search_end);
  return burst.start_aic_excess >= min_start_aic_excess ? burst : pick;
}

}  // namespace bouncecal::audio
