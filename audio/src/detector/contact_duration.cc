#include "detector/contact_duration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>
#include <numeric>

#include "dsp/real_fft.h"

namespace bouncecal::audio {
namespace {

// h(x) = cos(pi x) / (1 - 4 x^2), the half-sine's spectrum over its impulse, is used up to this
// x = f tau and frozen beyond: its first zero is at 1.5, and past it the ratio of two such
// spectra is a ratio of sidelobes that depends on the exact shape of a real pulse (Hertz's is
// not quite a half-sine), not on its duration. A duration so long that the whole band lies beyond
// it leaves every ratio flat, as one too short to matter does. Frozen at 1.2 instead, the steel
// plate's modes above it read a 142 us contact as 108 us (131 us at 1.45).
constexpr double kShapeLimit = 1.45;
constexpr int kShapeTableSteps = 1200;

// Hertz: tau ~ v^-1/5, and the impulse m (1 + e) v grows as v.
constexpr double kDurationExponent = -0.2;
// Impulse ratios outside this range are not a ball's bounces of one drop (or not one ball's).
constexpr double kMinImpulseRatio = 1e-3;
constexpr double kMaxImpulseRatio = 1e3;
constexpr int kImpulseIterations = 3;

// The search for the template's duration: a log grid from a contact far shorter than a sample at
// 48 kHz to a soft ball's (rubber, ~1-3 ms), refined by a parabola in ln tau.
constexpr double kShortestS = 2e-6;
constexpr double kLongestS = 8e-3;
constexpr int kGridPoints = 48;

// The impacts that fix the template's duration: those whose duration differs most from it (the
// weakest), since a ratio near 1 carries no information on it; more add little and cost time.
constexpr std::size_t kMaxFitImpacts = 32;
constexpr std::size_t kMinFitImpacts = 3;
// The estimate is used when the impacts agree on it to this (jackknife sd of ln tau_t): a 35 %
// error of tau_t leaves 35 % of the drift, which the stated sigmas then carry.
constexpr double kMaxTemplateLogSd = 0.35;

// Below this rate the band ends at 8-10 kHz, where a 50-70 us contact's spectrum has fallen by
// less than 15 % and the ratios' curvature is lost in the ringing of earlier impacts: on a
// ping-pong ball on a counter at 16 kHz the fit gave 113-117 us for a 47 us contact (48 kHz:
// 46.5 us), and its correction worsened the codec bench's 16 kHz onset error p95 from 185 to
// 227 us. There an estimate is kept only where the band holds its spectrum's first zero
// (f tau = 1.5 at 0.45 of the rate: 208 us at 16 kHz, 417 us at 8 kHz), as a soft ball's does:
// the 16 kHz rubber ball on a table (0.73 ms at its first bounce) was otherwise left with the
// alignment's drift, onsets from -110 to +122 us of the drop's median over 10 bounces at a
// stated 30-50 us (detector_accuracy_bench, in2sig 81 %).
constexpr int kMinSampleRateHz = 20000;
constexpr double kLowRateBandFraction = 0.45;
constexpr double kLowRateMinShape = 1.5;  // f tau at the half-sine spectrum's first zero
constexpr double kLowRateMaxPowerBeyondZero = 0.5;

// Bins whose template power is below this fraction of the strongest carry noise, not response.
constexpr double kMinBinPowerFraction = 1e-4;

class HalfSineSpectrum {
 public:
  HalfSineSpectrum() {
    for (int i = 0; i <= kShapeTableSteps; ++i) {
      const double x = kShapeLimit * i / kShapeTableSteps;
      const double denominator = 1 - 4 * x * x;
      // At x = 1/2 both cos(pi x) and 1 - 4 x^2 vanish; the limit is pi / 4.
      table_[static_cast<std::size_t>(i)] = std::fabs(denominator) < 1e-9
                                                ? std::numbers::pi / 4
                                                : std::cos(std::numbers::pi * x) / denominator;
    }
  }
  double operator()(double x) const {
    if (x >= kShapeLimit) return table_.back();
    const double position = x * (kShapeTableSteps / kShapeLimit);
    const auto i = static_cast<std::size_t>(position);
    const double f = position - static_cast<double>(i);
    return table_[i] + f * (table_[i + 1] - table_[i]);
  }

 private:
  std::array<double, kShapeTableSteps + 1> table_{};
};

// One response against the template, over the bins the fit uses.
struct CrossSpectrum {
  std::vector<double> cross;           // Re(conj(T) B), the sub-sample delay undone
  std::vector<double> template_power;  // |T|^2 of the template cut to the same length
  double energy = 0;                   // sum |B|^2
};

struct Fit {
  double rho2 = 0;
  double ratio = 1;  // tau_k / tau_t
};

class RatioFitter {
 public:
  RatioFitter(const std::vector<double>& frequencies, const HalfSineSpectrum& shape)
      : frequencies_(frequencies), shape_(shape) {}

  // The template's h(f tau_t) at every bin, for one tau_t.
  std::vector<double> TemplateShape(double tau_s) const {
    std::vector<double> h(frequencies_.size());
    for (std::size_t j = 0; j < h.size(); ++j) h[j] = shape_(frequencies_[j] * tau_s);
    return h;
  }

  Fit operator()(const CrossSpectrum& spectrum, double tau_s,
                 const std::vector<double>& template_shape) const {
    double gc = std::accumulate(spectrum.cross.begin(), spectrum.cross.end(), 0.0);
    double ggp =
        std::accumulate(spectrum.template_power.begin(), spectrum.template_power.end(), 0.0);
    Fit fit;
    for (int iteration = 0; iteration < kImpulseIterations; ++iteration) {
      const double impulse = std::clamp(std::fabs(gc / ggp), kMinImpulseRatio, kMaxImpulseRatio);
      fit.ratio = std::pow(impulse, kDurationExponent);
      const double tau_k = tau_s * fit.ratio;
      gc = 0;
      ggp = 0;
      for (std::size_t j = 0; j < spectrum.cross.size(); ++j) {
        const double g = shape_(frequencies_[j] * tau_k) / template_shape[j];
        gc += g * spectrum.cross[j];
        ggp += g * g * spectrum.template_power[j];
      }
    }
    fit.rho2 = ggp > 0 && spectrum.energy > 0 ? gc * gc / (ggp * spectrum.energy) : 0.0;
    return fit;
  }

 private:
  const std::vector<double>& frequencies_;
  const HalfSineSpectrum& shape_;
};

// The grid index and parabola-refined ln tau minimising q; NaN at the grid's edges (the minimum
// may lie beyond).
double RefinedMinimum(const std::vector<double>& q, const std::vector<double>& log_tau) {
  const auto best = static_cast<std::size_t>(std::min_element(q.begin(), q.end()) - q.begin());
  if (best == 0 || best + 1 == q.size()) return std::numeric_limits<double>::quiet_NaN();
  const double left = q[best - 1];
  const double right = q[best + 1];
  const double curvature = left - 2 * q[best] + right;
  const double step = log_tau[1] - log_tau[0];
  const double shift = curvature > 0 ? 0.5 * (left - right) / curvature : 0.0;
  return log_tau[best] + std::clamp(shift, -0.5, 0.5) * step;
}

}  // namespace

ContactDurations EstimateContactDurations(std::span<const float> templ,
                                          const std::vector<AlignedResponse>& responses,
                                          int sample_rate_hz, std::size_t min_samples) {
  ContactDurations result;
  result.ratios.assign(responses.size(), 1.0);
  std::size_t longest = 0;
  for (const auto& response : responses) longest = std::max(longest, response.samples.size());
  longest = std::min(longest, templ.size());
  if (longest < 4 || responses.size() < kMinFitImpacts) return result;
  const int size = static_cast<int>(longest + (longest % 2));
  RealFft fft(size);
  const auto bins = static_cast<std::size_t>(size / 2 + 1);
  const double rate = sample_rate_hz;
  // The template cut to each response's length, transformed once per length.
  std::map<std::size_t, std::vector<std::complex<float>>> template_spectra;
  const auto template_spectrum = [&](std::size_t n) -> const std::vector<std::complex<float>>& {
    auto it = template_spectra.find(n);
    if (it != template_spectra.end()) return it->second;
    std::fill(fft.real().begin(), fft.real().end(), 0.0f);
    std::copy_n(templ.begin(), n, fft.real().begin());
    fft.Forward();
    return template_spectra
        .emplace(n, std::vector<std::complex<float>>(fft.spectrum().begin(), fft.spectrum().end()))
        .first->second;
  };
  // Bins with the template's energy, chosen once on the full-length template.
  const auto& full_template = template_spectrum(longest);
  double strongest = 0;
  for (const auto& value : full_template) strongest = std::max(strongest, double(std::norm(value)));
  std::vector<std::size_t> used_bins;
  std::vector<double> frequencies;
  for (std::size_t j = 1; j < bins; ++j) {
    if (std::norm(full_template[j]) >= kMinBinPowerFraction * strongest) {
      used_bins.push_back(j);
      frequencies.push_back(rate * static_cast<double>(j) / size);
    }
  }
  if (used_bins.empty()) return result;
  std::vector<CrossSpectrum> spectra(responses.size());
  for (std::size_t r = 0; r < responses.size(); ++r) {
    const std::size_t n = std::min(responses[r].samples.size(), longest);
    if (n < 4) continue;
    const auto& t = template_spectrum(n);
    std::fill(fft.real().begin(), fft.real().end(), 0.0f);
    std::copy_n(responses[r].samples.begin(), n, fft.real().begin());
    fft.Forward();
    const auto b = fft.spectrum();
    CrossSpectrum& spectrum = spectra[r];
    for (std::size_t j = 0; j < bins; ++j) spectrum.energy += std::norm(std::complex<double>(b[j]));
    for (std::size_t j : used_bins) {
      // The response is the template delayed by `fraction` samples: advance it back.
      const double phase = 2 * std::numbers::pi * static_cast<double>(j) * responses[r].fraction /
                           static_cast<double>(size);
      const std::complex<double> advanced = std::complex<double>(b[j]) * std::polar(1.0, phase);
      spectrum.cross.push_back((std::conj(std::complex<double>(t[j])) * advanced).real());
      spectrum.template_power.push_back(std::norm(std::complex<double>(t[j])));
    }
  }
  const HalfSineSpectrum shape;
  const RatioFitter fitter(frequencies, shape);
  // The fit's impacts: full enough responses, the weakest first (their durations differ most).
  std::vector<std::pair<double, std::size_t>> by_impulse;
  for (std::size_t r = 0; r < responses.size(); ++r) {
    if (!responses[r].informs_fit || responses[r].samples.size() < min_samples ||
        spectra[r].cross.empty()) {
      continue;
    }
    const auto& s = spectra[r];
    const double power = std::accumulate(s.template_power.begin(), s.template_power.end(), 0.0);
    const double impulse = std::fabs(std::accumulate(s.cross.begin(), s.cross.end(), 0.0) / power);
    by_impulse.emplace_back(impulse, r);
  }
  std::sort(by_impulse.begin(), by_impulse.end());
  if (by_impulse.size() > kMaxFitImpacts) by_impulse.resize(kMaxFitImpacts);
  if (by_impulse.size() < kMinFitImpacts) return result;
  std::vector<double> log_tau(kGridPoints);
  for (int i = 0; i < kGridPoints; ++i) {
    log_tau[static_cast<std::size_t>(i)] =
        std::log(kShortestS) + (std::log(kLongestS) - std::log(kShortestS)) * i / (kGridPoints - 1);
  }
  // Each impact's term of the likelihood at every grid point, so leaving one out costs nothing.
  std::vector<std::vector<double>> terms(by_impulse.size(), std::vector<double>(kGridPoints));
  std::vector<double> total(kGridPoints, 0.0);
  for (int i = 0; i < kGridPoints; ++i) {
    const double tau = std::exp(log_tau[static_cast<std::size_t>(i)]);
    const std::vector<double> template_shape = fitter.TemplateShape(tau);
    for (std::size_t k = 0; k < by_impulse.size(); ++k) {
      const Fit fit = fitter(spectra[by_impulse[k].second], tau, template_shape);
      const double term = std::log(std::max(1.0 - fit.rho2, 1e-12));
      terms[k][static_cast<std::size_t>(i)] = term;
      total[static_cast<std::size_t>(i)] += term;
    }
  }
  const double estimate = RefinedMinimum(total, log_tau);
  if (!std::isfinite(estimate)) return result;
  // Jackknife over the impacts (Efron & Stein 1981): each left out once.
  std::vector<double> left_out;
  std::vector<double> q(kGridPoints);
  for (std::size_t k = 0; k < by_impulse.size(); ++k) {
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = total[i] - terms[k][i];
    const double value = RefinedMinimum(q, log_tau);
    if (!std::isfinite(value)) return result;
    left_out.push_back(value);
  }
  const double count = static_cast<double>(left_out.size());
  const double mean = std::accumulate(left_out.begin(), left_out.end(), 0.0) / count;
  double spread = 0;
  for (double value : left_out) spread += (value - mean) * (value - mean);
  const double log_sd = std::sqrt((count - 1) / count * spread);
  if (log_sd > kMaxTemplateLogSd) return result;
  if (sample_rate_hz < kMinSampleRateHz) {
    const double tau_s = std::exp(estimate);
    if (tau_s * kLowRateBandFraction * rate < kLowRateMinShape) return result;
    // A contact that long puts nearly all of an impact's response below its spectrum's first
    // zero; an estimate with most of the template's power beyond it read the plate's modes, not
    // the contact (measured at 16 kHz: 0.1-3.6 % beyond it for true 0.3-0.7 ms contacts,
    // 99.6-99.9 % for the 0.95 and 1.0 ms read off 50-70 us contacts in codec_timing_bench).
    double beyond = 0;
    double total_power = 0;
    for (std::size_t j = 1; j < bins; ++j) {
      const double power = std::norm(full_template[j]);
      total_power += power;
      if (rate * static_cast<double>(j) / size * tau_s > kLowRateMinShape) beyond += power;
    }
    if (beyond > kLowRateMaxPowerBeyondZero * total_power) return result;
  }
  result.template_s = std::exp(estimate);
  result.template_log_sd = log_sd;
  result.impacts_used = static_cast<int>(by_impulse.size());
  const std::vector<double> template_shape = fitter.TemplateShape(result.template_s);
  for (std::size_t r = 0; r < responses.size(); ++r) {
    if (spectra[r].cross.empty()) continue;
    result.ratios[r] = fitter(spectra[r], result.template_s, template_shape).ratio;
  }
  return result;
}

}  // namespace bouncecal::audio
