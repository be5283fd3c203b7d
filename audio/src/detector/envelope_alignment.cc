#include "detector/envelope_alignment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "detector/lag_dots.h"

namespace bouncecal::audio {
namespace {

// Octave band edges; a band is used where its upper edge is below 0.45 of the rate.
constexpr double kBandEdgesHz[] = {250, 500, 1000, 2000, 4000, 8000, 16000};
static_assert(std::size(kBandEdgesHz) == EnvelopeAligner::kMaxBands + 1);
// Rate of the decimated envelopes: a band's envelope varies no faster than its width allows,
// and the lag is refined below a step by the parabola.
constexpr double kEnvelopeRateHz = 12000;
// Share of the strongest band's energy a band of the template needs to be compared (a codec
// drops the bands it cannot afford; their envelopes are then noise).
constexpr double kMinBandShare = 0.01;

// Second-order band-pass (RBJ cookbook, 0 dB at the centre); each band runs it twice for
// steeper skirts.
BandPassSection BandPassFor(double low_hz, double high_hz, int rate_hz) {
  const double f0 = std::sqrt(low_hz * high_hz);
  const double q = f0 / (high_hz - low_hz);
  const double w0 = 2 * std::numbers::pi * f0 / rate_hz;
  const double alpha = std::sin(w0) / (2 * q);
  const double a0 = 1 + alpha;
  return {alpha / a0, -alpha / a0, -2 * std::cos(w0) / a0, (1 - alpha) / a0};
}

// Pearson correlation of a[a_start, a_start + n) with b[b_start + k, b_start + k + n) for k in
// [0, lags): the template centred once, the target's windowed mean and energy from prefix sums,
// so each lag costs one product a sample, many lags at once (lag_dots.h: a tenth of analysing
// ub-mth337 pingpong as AAC went here when each lag summed in double on its own).
std::vector<double> PearsonCurve(const std::vector<float>& a, std::int64_t a_start,
                                 const std::vector<float>& b, std::int64_t b_start, std::int64_t n,
                                 std::int64_t lags) {
  std::vector<float> centred(static_cast<std::size_t>(n));
  double mean_a = 0;
  for (std::int64_t t = 0; t < n; ++t) mean_a += a[static_cast<std::size_t>(a_start + t)];
  mean_a /= static_cast<double>(n);
  double var_a = 0;
  for (std::int64_t t = 0; t < n; ++t) {
    const double value = a[static_cast<std::size_t>(a_start + t)] - mean_a;
    centred[static_cast<std::size_t>(t)] = static_cast<float>(value);
    var_a += value * value;
  }
  const auto span = static_cast<std::size_t>(n + lags - 1);
  std::vector<double> sum(span + 1, 0.0);
  std::vector<double> squares(span + 1, 0.0);
  for (std::size_t i = 0; i < span; ++i) {
    const double y = b[static_cast<std::size_t>(b_start) + i];
    sum[i + 1] = sum[i] + y;
    squares[i + 1] = squares[i] + y * y;
  }
  std::vector<double> curve(static_cast<std::size_t>(lags), 0.0);
  if (var_a <= 0) return curve;
  std::vector<float> dots(static_cast<std::size_t>(lags));
  LagDotProducts(centred.data(), b.data() + b_start, n, lags, dots.data());
  for (std::int64_t k = 0; k < lags; ++k) {
    const auto from = static_cast<std::size_t>(k);
    const auto to = static_cast<std::size_t>(k + n);
    const double sb = sum[to] - sum[from];
    const double var_b = squares[to] - squares[from] - sb * sb / static_cast<double>(n);
    if (var_b <= 0) continue;
    curve[from] = dots[from] / std::sqrt(var_a * var_b);
  }
  return curve;
}

// The peak's own lobe in a curve: indices where it keeps falling away from best.
std::pair<std::int64_t, std::int64_t> Lobe(const std::vector<double>& c, std::int64_t best) {
  std::int64_t lo = best;
  while (lo > 0 && c[static_cast<std::size_t>(lo - 1)] < c[static_cast<std::size_t>(lo)]) --lo;
  std::int64_t hi = best;
  const auto size = static_cast<std::int64_t>(c.size());
  while (hi + 1 < size && c[static_cast<std::size_t>(hi + 1)] < c[static_cast<std::size_t>(hi)]) {
    ++hi;
  }
  return {lo, hi};
}

// A curve's peak refined by a parabola through it and its neighbours (best not at an edge).
double Refine(const std::vector<double>& c, std::int64_t best, double* curvature) {
  const double left = c[static_cast<std::size_t>(best - 1)];
  const double mid = c[static_cast<std::size_t>(best)];
  const double right = c[static_cast<std::size_t>(best + 1)];
  *curvature = left - 2 * mid + right;
  return static_cast<double>(best) +
         (*curvature < 0 ? std::clamp(0.5 * (left - right) / *curvature, -0.5, 0.5) : 0.0);
}

// The standard error, over the bands, of the mean correlation's rise from lag `from` to lag `to`:
// how much of that rise the bands' differences alone could make. Taken on each band's own rise,
// so what the bands share at both lags (a band correlating better or worse all along) cancels.
double RiseStandardError(const std::vector<std::vector<double>>& curves, std::size_t from,
                         std::size_t to) {
  if (curves.size() < 2) return 0.0;
  const auto bands = static_cast<double>(curves.size());
  double mean = 0;
  for (const auto& curve : curves) mean += (curve[to] - curve[from]) / bands;
  double ss = 0;
  for (const auto& curve : curves) {
    const double rise = curve[to] - curve[from] - mean;
    ss += rise * rise;
  }
  return std::sqrt(ss / (bands - 1) / bands);
}

// The best other alignment than the mean's peak at best: the highest lag beyond a point where
// the mean, walking away from the peak, rises out of the lowest value passed by more than the
// bands' standard error of that rise (a dip the bands resolve; -1 where there is none). A
// wiggle on the peak's own flank is not another alignment: zaky-ptv-pingpong's pingpongvid2 as
// MP3 128k, 4th bounce, rose 0.005 out of a dip at 0.400 on the way up to the peak at 0.510 (the
// bands' standard error of that rise: 0.018), where the strictly falling lobe (Lobe) stops; taken
// for a rival 0.105 below the peak, it made the alignment ambiguous, and the detector's onset,
// 1.19 ms early, was kept. The bands still vote within Lobe: a lobe widened to the dips (tried)
// let bands with a second bump far out on the flank vote there (fr4nci Audio_1 as AAC 128k:
// eta-bar +-0.00029 -> +-0.00131, ub-mth337 pingpong +-0.00019 -> +-0.00068, none closer to the
// WAV's, and zaky's MP3 copy back at 0.2498).
double ResolvedRival(const std::vector<std::vector<double>>& curves,
                     const std::vector<double>& mean, std::int64_t best) {
  const auto lags = static_cast<std::int64_t>(mean.size());
  double rival = -1;
  for (const std::int64_t direction : {std::int64_t{-1}, std::int64_t{1}}) {
    auto dip = static_cast<std::size_t>(best);
    bool resolved = false;
    for (std::int64_t k = best + direction; k >= 0 && k < lags; k += direction) {
      const auto at = static_cast<std::size_t>(k);
      if (!resolved && mean[at] < mean[dip]) {
        dip = at;
      } else if (resolved || mean[at] - mean[dip] > RiseStandardError(curves, dip, at)) {
        resolved = true;
        rival = std::max(rival, mean[at]);
      }
    }
  }
  return rival;
}

}  // namespace

EnvelopeAligner::EnvelopeAligner(int sample_rate_hz, std::span<const float> templ,
                                 std::int64_t lead, std::int64_t search,
                                 const EnvelopeAlignmentOptions& options)
    : options_(options), sample_rate_hz_(sample_rate_hz) {
  step_ = std::max<std::int64_t>(1, std::llround(sample_rate_hz / kEnvelopeRateHz));
  lead_ = lead / step_;
  pre_ = static_cast<std::int64_t>(std::ceil(options_.pre_s * sample_rate_hz / step_));
  // A pre-echo moves the detector's onset early, so the response may start up to the whole
  // search after it; before it, the window ends the envelope compared before the onset.
  after_ = search / step_;
  before_ = std::min(after_, lead_ - pre_ - 1);
  for (std::size_t b = 0; b + 1 < std::size(kBandEdgesHz); ++b) {
    if (kBandEdgesHz[b + 1] > 0.45 * sample_rate_hz) break;
    bands_.push_back(Band{kBandEdgesHz[b],
                          kBandEdgesHz[b + 1],
                          BandPassFor(kBandEdgesHz[b], kBandEdgesHz[b + 1], sample_rate_hz),
                          {}});
  }
  auto envelopes = Envelopes(templ);
  std::vector<double> energy(bands_.size(), 0.0);
  double strongest = 0;
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    bands_[b].templ = std::move(envelopes[b]);
    for (std::size_t t = static_cast<std::size_t>(lead_ - pre_); t < bands_[b].templ.size(); ++t) {
      energy[b] += bands_[b].templ[t];
    }
    strongest = std::max(strongest, energy[b]);
  }
  used_.assign(bands_.size(), false);
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    used_[b] = strongest > 0 && energy[b] >= kMinBandShare * strongest;
  }
}

std::vector<std::vector<float>> EnvelopeAligner::Envelopes(std::span<const float> window) const {
  const std::size_t bands = bands_.size();
  const std::size_t size = window.size();
  // Every band's two sections in one pass over the window, the bands side by side in fixed-size
  // lanes: each section's recursion waits on its own last output, so one band at a time ran at
  // the latency of that chain (a tenth of analysing a 10-minute AAC copy), while the bands'
  // chains are independent and vectorise across the lanes. Per band the same operations in the
  // same order as two passes one after the other, so the same envelopes to the last bit. Lanes
  // past the bands used run on zero coefficients and are ignored.
  using Lanes = std::array<double, kMaxBands>;
  Lanes b0{}, b2{}, a1{}, a2{};
  for (std::size_t b = 0; b < bands; ++b) {
    b0[b] = bands_[b].filter.b0;
    b2[b] = bands_[b].filter.b2;
    a1[b] = bands_[b].filter.a1;
    a2[b] = bands_[b].filter.a2;
  }
  Lanes x1{}, x2{}, y1{}, y2{};  // the first section's state
  Lanes u1{}, u2{}, v1{}, v2{};  // the second's
  // Running sums of each band's squared output, lane-interleaved: prefix[i * kMaxBands + b] is
  // the sum over band b's first i samples.
  std::vector<double> prefix((size + 1) * kMaxBands, 0.0);
  for (std::size_t i = 0; i < size; ++i) {
    const double x = window[i];
    double* before = prefix.data() + i * kMaxBands;
    double* after = before + kMaxBands;
    for (std::size_t b = 0; b < kMaxBands; ++b) {
      const double y = b0[b] * x + b2[b] * x2[b] - a1[b] * y1[b] - a2[b] * y2[b];
      x2[b] = x1[b];
      x1[b] = x;
      y2[b] = y1[b];
      y1[b] = y;
      const double v = b0[b] * y + b2[b] * u2[b] - a1[b] * v1[b] - a2[b] * v2[b];
      u2[b] = u1[b];
      u1[b] = y;
      v2[b] = v1[b];
      v1[b] = v;
      after[b] = before[b] + v * v;
    }
  }
  std::vector<std::vector<float>> out;
  const auto decimated = static_cast<std::int64_t>(size) / step_;
  const auto length = static_cast<std::int64_t>(size);
  for (std::size_t b = 0; b < bands; ++b) {
    // Box over half a period of the band's lowest frequency (the square's ripple), at least one
    // decimation step; centred, so the smoothing delays every impact alike (none).
    const auto box =
        std::max<std::int64_t>(step_, std::llround(0.5 * sample_rate_hz_ / bands_[b].low_hz));
    const auto sum_to = [&](std::int64_t i) {
      return prefix[static_cast<std::size_t>(i) * kMaxBands + b];
    };
    std::vector<float> envelope(static_cast<std::size_t>(decimated), 0.0f);
    for (std::int64_t k = 0; k < decimated; ++k) {
      const std::int64_t centre = k * step_ + step_ / 2;
      const std::int64_t from = std::clamp<std::int64_t>(centre - box / 2, 0, length);
      const std::int64_t to = std::clamp<std::int64_t>(centre - box / 2 + box, 0, length);
      envelope[static_cast<std::size_t>(k)] = static_cast<float>(
          (sum_to(to) - sum_to(from)) / static_cast<double>(std::max<std::int64_t>(1, to - from)));
    }
    out.push_back(std::move(envelope));
  }
  return out;
}

EnvelopeAlignment EnvelopeAligner::Align(std::span<const float> target, std::int64_t n) const {
  EnvelopeAlignment result;
  if (before_ < 2 || after_ < 2) return result;
  const std::int64_t length = pre_ + n / step_;
  const auto envelopes = Envelopes(target);
  const std::int64_t lags = before_ + after_ + 1;
  const std::int64_t templ_start = lead_ - pre_;
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    if (used_[b] && static_cast<std::int64_t>(bands_[b].templ.size()) < templ_start + length) {
      return result;
    }
  }
  if (static_cast<std::int64_t>(envelopes.empty() ? 0 : envelopes[0].size()) <
      templ_start + after_ + length) {
    return result;
  }
  std::vector<std::vector<double>> curves;
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    if (!used_[b]) continue;
    curves.push_back(PearsonCurve(bands_[b].templ, templ_start, envelopes[b], templ_start - before_,
                                  length, lags));
  }
  if (curves.empty()) return result;
  std::vector<double> mean(static_cast<std::size_t>(lags), 0.0);
  for (const auto& curve : curves) {
    for (std::size_t k = 0; k < mean.size(); ++k) mean[k] += curve[k] / curves.size();
  }
  const std::int64_t best = std::max_element(mean.begin(), mean.end()) - mean.begin();
  const double rho = mean[static_cast<std::size_t>(best)];
  if (best == 0 || best == lags - 1) return result;
  const auto [lo, hi] = Lobe(mean, best);
  const double rival = ResolvedRival(curves, mean, best);
  double curvature = 0;
  const double peak = Refine(mean, best, &curvature);
  // Each band votes with its own peak inside the mean's lobe, where it correlates there. A
  // band's best lag elsewhere does not veto: one band's envelope can hold two bumps (a room
  // echo, two modes beating), which the other bands resolve; the mean's margin is the test of
  // ambiguity.
  std::vector<double> band_peaks;
  for (const auto& curve : curves) {
    std::int64_t own = std::max(lo, std::int64_t{1});
    for (std::int64_t k = own; k <= std::min(hi, lags - 2); ++k) {
      if (curve[static_cast<std::size_t>(k)] > curve[static_cast<std::size_t>(own)]) own = k;
    }
    const double at = curve[static_cast<std::size_t>(own)];
    const bool local_peak = at >= curve[static_cast<std::size_t>(own - 1)] &&
                            at >= curve[static_cast<std::size_t>(own + 1)];
    if (at < options_.band_correlation || !local_peak) continue;
    double band_curvature = 0;
    band_peaks.push_back(Refine(curve, own, &band_curvature));
  }
  result.bands = static_cast<int>(band_peaks.size());
  result.correlation = rho;
  result.lag_samples = (peak - static_cast<double>(before_)) * static_cast<double>(step_);
  // Time-delay estimation from the mean correlation: its curvature sets the correlation time
  // T = sqrt(rho / -c) (steps), the compared envelope holds about length / T independent
  // values, and the residual 1 - rho^2 spreads over them: var = T^2 (1 - rho^2) /
  // (rho^2 length / T).
  const double correlation_time =
      curvature < 0 ? std::sqrt(rho / -curvature) : static_cast<double>(lags);
  const double independent = std::max(1.0, static_cast<double>(length) / correlation_time);
  const double r2 = std::clamp(rho * rho, 1e-6, 1.0);
  const double width = correlation_time * std::sqrt((1 - r2) / (r2 * independent));
  double spread = 0;
  if (band_peaks.size() >= 2) {
    double m = 0;
    for (double p : band_peaks) m += p / band_peaks.size();
    double ss = 0;
    for (double p : band_peaks) ss += (p - m) * (p - m);
    // The standard error of the bands' mean peak.
    spread = std::sqrt(ss / (band_peaks.size() - 1) / band_peaks.size());
  }
  result.sigma_samples = std::max(1.0, std::hypot(width, spread)) * static_cast<double>(step_);
  result.usable = rho >= options_.min_correlation && rho - rival >= options_.min_peak_margin &&
                  result.bands >= options_.min_bands;
  return result;
}

}  // namespace bouncecal::audio
