#include "scatter_posterior.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace bouncecal::calibrate::internal {
namespace {

// The grid in ln tau: a coarse pass over everything from far below the smallest timing sd (where
// the prior vanishes as tau^2) to tau = 1 (eta is in [0, 1], so no sd of it can be larger), then
// a fine one over where the posterior is within e^-30 of its peak: 200 nodes resolve a posterior
// of relative width 1 / sqrt(2 impacts) up to thousands of impacts.
constexpr int kCoarseNodes = 160;
constexpr int kFineNodes = 200;
constexpr double kBelowSmallestTiming = 1e-3;
constexpr double kLargestTau = 1.0;
constexpr double kLogSpan = 30.0;

struct Design {
  Eigen::MatrixXd x;  // impacts x (sequences [+ contact] + slope)
  Eigen::VectorXd y;
  Eigen::VectorXd timing_variance;
  Eigen::Index contact_column = -1;  // the contact duration's column, if any
};

// The contact duration's coefficient c (a change of ln t_c of the simulated drop) has a normal
// prior of this sd: the DEM's contact may be the ball's to within a factor e either way at one
// sd (the law's default stiffness, or a linear law's speed-independent duration against a Hertz
// contact's v^-1/5 over a 5-10x range of speeds), not any duration at all, which a flat prior
// would allow and which took the test's power against a viscoelastic Hertz material at 1 %
// scatter from 84 % to 16 % (calibrate_chain_coverage_bench, docs/calibration.md).
constexpr double kContactLogSd = 1.0;

struct AtTau {
  double log_density = -std::numeric_limits<double>::infinity();  // in ln tau, unnormalised
  double slope = 0;
  double slope_variance = 0;
};

AtTau Evaluate(const Design& design, double tau, bool with_slope) {
  AtTau result;
  const Eigen::Index p = design.x.cols();
  const Eigen::VectorXd w = (design.timing_variance.array() + tau * tau).inverse();
  Eigen::MatrixXd a = design.x.transpose() * w.asDiagonal() * design.x;
  if (design.contact_column >= 0) {
    a(design.contact_column, design.contact_column) += 1 / (kContactLogSd * kContactLogSd);
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(a);
  if (llt.info() != Eigen::Success) return result;
  const Eigen::VectorXd beta = llt.solve(design.x.transpose() * w.asDiagonal() * design.y);
  const Eigen::VectorXd e = design.y - design.x * beta;
  double q = (w.array() * e.array().square()).sum();
  if (design.contact_column >= 0) {
    q +=
        beta[design.contact_column] * beta[design.contact_column] / (kContactLogSd * kContactLogSd);
  }
  const Eigen::MatrixXd l = llt.matrixL();
  double log_det_a = 0;
  for (Eigen::Index i = 0; i < p; ++i) log_det_a += 2 * std::log(l(i, i));
  // tr(P^2) with P = W^1/2 (I - H) W^1/2, H = C C', C = W^1/2 X L^-T:
  //   sum w^2 - 2 sum w_i^2 |c_i|^2 + |C' W C|_F^2.
  const Eigen::MatrixXd c =
      llt.matrixL()
          .solve((w.array().sqrt().matrix().asDiagonal() * design.x).transpose())
          .transpose();
  const Eigen::MatrixXd m = c.transpose() * w.asDiagonal() * c;
  const double trace = w.squaredNorm() -
                       2 * (w.array().square() * c.rowwise().squaredNorm().array()).sum() +
                       m.squaredNorm();
  if (!(trace > 0)) return result;
  result.log_density = 2 * std::log(tau) + 0.5 * std::log(trace) + 0.5 * w.array().log().sum() -
                       0.5 * log_det_a - 0.5 * q;
  if (with_slope) {
    result.slope = beta[p - 1];
    result.slope_variance = llt.solve(Eigen::VectorXd::Unit(p, p - 1))[p - 1];
  }
  return result;
}

double Sum(const std::vector<double>& values) {
  double total = 0;
  for (double v : values) total += v;
  return total;
}

// The p-quantile of `values` under `weight` (not necessarily sorted), interpolated in ln value
// between neighbouring nodes.
double WeightedQuantile(const std::vector<double>& values, const std::vector<double>& weight,
                        double p) {
  if (values.empty()) return 0.0;
  std::vector<size_t> order(values.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return values[a] < values[b]; });
  double cumulative = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    const size_t i = order[k];
    const double next = cumulative + weight[i];
    if (next >= p) {
      if (k == 0) return values[i];
      const double previous = values[order[k - 1]];
      const double f = weight[i] > 0 ? (p - cumulative) / weight[i] : 0.0;
      return std::exp(std::log(previous) + f * (std::log(values[i]) - std::log(previous)));
    }
    cumulative = next;
  }
  return values[order.back()];
}

}  // namespace

double ScatterPosterior::TauQuantile(double p) const { return WeightedQuantile(tau, weight, p); }

double ScatterPosterior::TimingScaleQuantile(double p) const {
  return WeightedQuantile(timing_scale, weight, p);
}

namespace {

// The timing scales phi (FitScatterPosterior with scale_timing): log-uniform on [1/8, 4], in
// steps of a third of an octave.
constexpr int kTimingScaleNodes = 16;
// Per timing scale a coarser grid in ln tau: the interval mixes over the whole (tau, phi) grid,
// and 60 + 80 nodes per slice keep the cost of a fit within 5x of the unscaled posterior's.
constexpr int kScaledCoarseNodes = 60;
constexpr int kScaledFineNodes = 80;
constexpr double kSmallestTimingScale = 0.125;
constexpr double kLargestTimingScale = 4.0;

}  // namespace

double ScatterPosterior::SlopeAboveZero() const {
  double above = 0;
  for (size_t i = 0; i < tau.size(); ++i) {
    const double sd = std::sqrt(slope_variance[i]);
    above += weight[i] * 0.5 * std::erfc(-slope[i] / (sd * std::numbers::sqrt2));
  }
  return above;
}

double ScatterPosterior::SlopeMean() const {
  double mean = 0;
  for (size_t i = 0; i < tau.size(); ++i) mean += weight[i] * slope[i];
  return mean;
}

double ScatterPosterior::SlopeSd() const {
  const double mean = SlopeMean();
  double second = 0;
  for (size_t i = 0; i < tau.size(); ++i)
    second += weight[i] * (slope_variance[i] + slope[i] * slope[i]);
  return std::sqrt(std::max(0.0, second - mean * mean));
}

bool ScatterPosterior::SlopeExcludesZero(double level) const {
  const double above = SlopeAboveZero();
  return 2 * std::min(above, 1 - above) < 1 - level;
}

ScatterPosterior FitScatterPosterior(const std::vector<AdequacyImpact>& impacts, bool with_slope,
                                     bool scale_timing) {
  ScatterPosterior posterior;
  posterior.with_slope = with_slope;
  std::map<int, int> columns;
  std::map<int, std::pair<double, double>> log_speed_range;
  for (const auto& impact : impacts) {
    columns.emplace(impact.sequence, static_cast<int>(columns.size()));
    // A zero timing variance (hand-made impact times) would make a weight infinite at tau -> 0.
    const double v = std::log(std::max(impact.speed_mps, 1e-9));  // the slope's regressor
    auto [it, inserted] = log_speed_range.emplace(impact.sequence, std::make_pair(v, v));
    it->second.first = std::min(it->second.first, v);
    it->second.second = std::max(it->second.second, v);
  }
  posterior.impacts = static_cast<int>(impacts.size());
  posterior.sequences = static_cast<int>(columns.size());
  // The contact's duration as a nuisance (AdequacyImpact::contact_sensitivity): one more column,
  // integrated out over its normal prior (kContactLogSd), for the trend test and the interval's
  // scatter alike. Without it the simulated drop's contact, a smooth pattern in k, is read as
  // per-impact scatter: on drops without scatter tau_w's median was 7e-5 to 1.7e-4 in eta and made
  // 76-99 % of the interval's variance (calibrate_chain_coverage_bench, docs/calibration.md).
  const bool contact_column =
      std::any_of(impacts.begin(), impacts.end(),
                  [](const AdequacyImpact& impact) { return impact.contact_sensitivity != 0; });
  posterior.dof = posterior.impacts - posterior.sequences - (with_slope ? 1 : 0);
  if (posterior.dof < 1) return posterior;
  if (with_slope &&
      std::none_of(log_speed_range.begin(), log_speed_range.end(),
                   [](const auto& entry) { return entry.second.second > entry.second.first; }))
    return posterior;

  Design design;
  const auto n = static_cast<Eigen::Index>(impacts.size());
  const Eigen::Index p = posterior.sequences + (contact_column ? 1 : 0) + (with_slope ? 1 : 0);
  design.x = Eigen::MatrixXd::Zero(n, p);
  design.y.resize(n);
  design.timing_variance.resize(n);
  double smallest_variance = std::numeric_limits<double>::infinity();
  posterior.speed_min_mps = posterior.speed_max_mps = std::max(impacts.front().speed_mps, 1e-9);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& impact = impacts[static_cast<size_t>(i)];
    const double speed = std::max(impact.speed_mps, 1e-9);
    design.x(i, columns[impact.sequence]) = 1;
    if (contact_column) {
      design.x(i, posterior.sequences) = impact.contact_sensitivity;
      design.contact_column = posterior.sequences;
    }
    if (with_slope) design.x(i, p - 1) = std::log(speed);
    design.y[i] = impact.residual;
    design.timing_variance[i] = std::max(impact.timing_variance, 1e-14);
    smallest_variance = std::min(smallest_variance, design.timing_variance[i]);
    posterior.speed_min_mps = std::min(posterior.speed_min_mps, speed);
    posterior.speed_max_mps = std::max(posterior.speed_max_mps, speed);
  }

  // For each timing scale, a coarse pass in ln tau, then the fine grid over the part that carries
  // the posterior; a node's weight is its density times its slice's spacing in ln tau (phi's
  // spacing is the same for every slice).
  posterior.timing_scaled = scale_timing;
  const int scales = scale_timing ? kTimingScaleNodes : 1;
  const int coarse_nodes = scale_timing ? kScaledCoarseNodes : kCoarseNodes;
  const int fine_nodes = scale_timing ? kScaledFineNodes : kFineNodes;
  std::vector<double> log_density;
  const Eigen::VectorXd stated_variance = design.timing_variance;
  for (int j = 0; j < scales; ++j) {
    const double phi =
        scale_timing ? std::exp(std::log(kSmallestTimingScale) +
                                (std::log(kLargestTimingScale) - std::log(kSmallestTimingScale)) *
                                    j / (kTimingScaleNodes - 1))
                     : 1.0;
    design.timing_variance = stated_variance * (phi * phi);
    const double low = std::log(kBelowSmallestTiming * phi * std::sqrt(smallest_variance));
    const double high = std::log(kLargestTau);
    const auto node = [](double from, double to, int count, int i) {
      return from + (to - from) * i / (count - 1);
    };
    std::vector<double> coarse(coarse_nodes);
    double peak = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < coarse_nodes; ++i) {
      coarse[static_cast<size_t>(i)] =
          Evaluate(design, std::exp(node(low, high, coarse_nodes, i)), with_slope).log_density;
      peak = std::max(peak, coarse[static_cast<size_t>(i)]);
    }
    if (!std::isfinite(peak)) continue;
    int first = coarse_nodes - 1, last = 0;
    for (int i = 0; i < coarse_nodes; ++i) {
      if (coarse[static_cast<size_t>(i)] > peak - kLogSpan) {
        first = std::min(first, i);
        last = std::max(last, i);
      }
    }
    const double fine_low = node(low, high, coarse_nodes, std::max(first - 1, 0));
    const double fine_high = node(low, high, coarse_nodes, std::min(last + 1, coarse_nodes - 1));
    const double log_spacing = std::log((fine_high - fine_low) / (fine_nodes - 1));
    for (int i = 0; i < fine_nodes; ++i) {
      const double tau = std::exp(node(fine_low, fine_high, fine_nodes, i));
      const AtTau at = Evaluate(design, tau, with_slope);
      posterior.tau.push_back(tau);
      posterior.timing_scale.push_back(phi);
      log_density.push_back(at.log_density + log_spacing);
      posterior.slope.push_back(at.slope);
      posterior.slope_variance.push_back(at.slope_variance);
    }
  }
  if (log_density.empty()) return posterior;
  const double fine_peak = *std::max_element(log_density.begin(), log_density.end());
  if (!std::isfinite(fine_peak)) return posterior;
  for (double value : log_density) posterior.weight.push_back(std::exp(value - fine_peak));
  const double total = Sum(posterior.weight);
  for (double& value : posterior.weight) value /= total;
  posterior.ok = true;
  return posterior;
}

}  // namespace bouncecal::calibrate::internal
