#include "synth/anti_aliasing_filter.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "bouncecal/error.h"
#include "dsp/real_fft.h"

namespace bouncecal::audio {
namespace {

constexpr int kMaxTaps = 1 << 16;
// The cepstrum of log|H| decays slowly near the stop-band zeros; a grid 64x the filter length
// keeps its time aliasing far below the stop band.
constexpr int kCepstrumGridFactor = 64;
// The floor under |H| before the logarithm, relative to delta: low enough not to lift the stop
// band, high enough to keep the cepstrum's dynamic range within double precision.
constexpr double kLogFloorBelowDelta = 1e-3;

int NextPowerOfTwo(int n) {
  int power = 1;
  while (power < n) power <<= 1;
  return power;
}

// Modified Bessel function of the first kind, order 0, by its power series (converges for all
// x; beta <= 20 here needs ~40 terms).
double BesselI0(double x) {
  double sum = 1.0;
  double term = 1.0;
  const double quarter_x2 = 0.25 * x * x;
  for (int k = 1; k < 500; ++k) {
    term *= quarter_x2 / (static_cast<double>(k) * k);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum;
}

// |H| on the grid of an FFT of the taps zero-padded to `size` (bins 0..size/2).
// |H| at f cycles per sample by the direct sum.
double MagnitudeAt(std::span<const double> taps, double f) {
  std::complex<double> sum = 0.0;
  for (size_t k = 0; k < taps.size(); ++k) {
    sum += taps[k] * std::polar(1.0, -2.0 * std::numbers::pi * f * static_cast<double>(k));
  }
  return std::abs(sum);
}

std::vector<double> MagnitudeGrid(std::span<const double> taps, int size) {
  RealFftDouble fft(size);
  const auto real = fft.real();
  std::fill(real.begin(), real.end(), 0.0);
  std::copy(taps.begin(), taps.end(), real.begin());
  fft.Forward();
  const auto spectrum = fft.spectrum();
  std::vector<double> magnitude(spectrum.size());
  for (size_t k = 0; k < magnitude.size(); ++k) {
    magnitude[k] = std::hypot(spectrum[k].real(), spectrum[k].imag());
  }
  return magnitude;
}

}  // namespace

double KaiserBeta(double attenuation_db) {
  const double a = attenuation_db;
  if (a > 50.0) return 0.1102 * (a - 8.7);
  if (a >= 21.0) return 0.5842 * std::pow(a - 21.0, 0.4) + 0.07886 * (a - 21.0);
  return 0.0;
}

std::vector<double> KaiserLowPass(int taps, double cutoff_cycles_per_sample, double beta) {
  std::vector<double> h(static_cast<size_t>(taps));
  const double half = 0.5 * (taps - 1);
  const double window_norm = BesselI0(beta);
  double sum = 0.0;
  for (int k = 0; k < taps; ++k) {
    const double n = k - half;
    const double x = 2.0 * cutoff_cycles_per_sample * n;
    const double sinc = n == 0.0 ? 1.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
    const double r = half > 0.0 ? n / half : 0.0;
    const double window = BesselI0(beta * std::sqrt(std::max(0.0, 1.0 - r * r))) / window_norm;
    h[static_cast<size_t>(k)] = 2.0 * cutoff_cycles_per_sample * sinc * window;
    sum += h[static_cast<size_t>(k)];
  }
  for (double& value : h) value /= sum;
  return h;
}

std::vector<double> MinimumPhase(std::span<const double> linear_phase, double floor_magnitude) {
  const int taps = static_cast<int>(linear_phase.size());
  const int size = NextPowerOfTwo(kCepstrumGridFactor * taps);
  const auto bins = static_cast<size_t>(size / 2 + 1);
  RealFftDouble fft(size);
  const auto real = fft.real();
  const auto spectrum = fft.spectrum();

  // log|H| (real and even) -> real cepstrum c[n] (real and even).
  const std::vector<double> magnitude = MagnitudeGrid(linear_phase, size);
  for (size_t k = 0; k < bins; ++k) {
    spectrum[k] = std::log(std::max(magnitude[k], floor_magnitude));
  }
  fft.Inverse();
  const double scale = 1.0 / size;
  // Folding c onto n >= 0 (c[0], 2 c[n], c[N/2]) makes the log-spectrum analytic: its
  // exponential has the same magnitude and all its zeros inside the unit circle.
  real[0] *= scale;
  for (int n = 1; n < size / 2; ++n) real[n] *= 2.0 * scale;
  real[size / 2] *= scale;
  std::fill(real.begin() + size / 2 + 1, real.end(), 0.0);
  fft.Forward();
  for (size_t k = 0; k < bins; ++k) spectrum[k] = std::exp(spectrum[k]);
  fft.Inverse();
  std::vector<double> h(real.begin(), real.begin() + taps);
  double sum = 0.0;
  for (double& value : h) {
    value *= scale;
    sum += value;
  }
  for (double& value : h) value /= sum;  // unit DC gain, as the linear-phase filter
  return h;
}

FilterFigures MeasureFilter(std::span<const double> taps, int oversampling,
                            double passband_edge_fraction, double stopband_edge_fraction) {
  const int size = std::max(1 << 12, NextPowerOfTwo(32 * static_cast<int>(taps.size())));
  const std::vector<double> magnitude = MagnitudeGrid(taps, size);
  const auto db = [](double value) { return 20.0 * std::log10(std::max(value, 1e-300)); };
  FilterFigures figures;
  // The band edges themselves, exactly: the response is steepest there, and a grid bin just
  // inside the stop band would miss dBs of it.
  figures.passband_ripple_db =
      std::abs(db(MagnitudeAt(taps, passband_edge_fraction / oversampling)));
  figures.stopband_attenuation_db = -db(MagnitudeAt(taps, stopband_edge_fraction / oversampling));
  for (size_t k = 0; k < magnitude.size(); ++k) {
    // Bin k is k / size cycles per high-rate sample, k * oversampling / size of the output rate.
    const double fraction = static_cast<double>(k) * oversampling / size;
    if (fraction <= passband_edge_fraction) {
      figures.passband_ripple_db = std::max(figures.passband_ripple_db, std::abs(db(magnitude[k])));
    } else if (fraction >= stopband_edge_fraction) {
      figures.stopband_attenuation_db =
          std::min(figures.stopband_attenuation_db, -db(magnitude[k]));
    }
  }
  return figures;
}

int ResolvedOversampling(const RecordingChain& chain, double sample_rate_hz) {
  if (chain.oversampling != 0) return chain.oversampling;
  // Where a 35 us half-sine's aliases sit 50 dB under its filtered peak (see RecordingChain).
  constexpr double kAutomaticHighRateHz = 384000.0;
  return std::max(8, static_cast<int>(std::ceil(kAutomaticHighRateHz / sample_rate_hz)));
}

AntiAliasingFilter DesignAntiAliasingFilter(const RecordingChain& chain, double sample_rate_hz) {
  const int m = ResolvedOversampling(chain, sample_rate_hz);
  const double p = chain.passband_edge_fraction;
  const double s = chain.stopband_edge_fraction;
  const double a = chain.stopband_attenuation_db;
  if (m < 2 || !(p > 0.0 && p < s && s <= 1.0 - p) || !(a >= 40.0 && a <= 150.0)) {
    throw ConfigError(
        "synthesis option chain: oversampling >= 2, 0 < passband_edge_fraction < "
        "stopband_edge_fraction <= 1 - passband_edge_fraction and stopband_attenuation_db in "
        "[40, 150] are needed; fix the chain options");
  }
  AntiAliasingFilter filter;
  filter.oversampling = m;
  // Kaiser's beta formula lands within ~0.3 dB of A; half a dB more leaves lengthening alone to
  // close the gap (within 4 % of the estimated length for 40-150 dB, 2-24x oversampling).
  filter.kaiser_beta = KaiserBeta(a + 0.5);
  filter.cutoff_cycles_per_sample = 0.5 * (p + s) / m;
  const double transition_rad = 2.0 * std::numbers::pi * (s - p) / m;
  int taps = static_cast<int>(std::ceil((a - 7.95) / (2.285 * transition_rad))) + 1;
  taps += 1 - taps % 2;  // odd: a whole-sample group delay
  const int give_up = taps + taps / 4;
  while (true) {
    if (taps > kMaxTaps) {
      throw ConfigError("synthesis option chain needs an anti-aliasing filter of " +
                        std::to_string(taps) + " taps (more than " + std::to_string(kMaxTaps) +
                        "); widen the transition band, lower stopband_attenuation_db or the "
                        "oversampling");
    }
    filter.taps = KaiserLowPass(taps, filter.cutoff_cycles_per_sample, filter.kaiser_beta);
    if (chain.phase == AdcFilterPhase::kMinimum) {
      filter.taps = MinimumPhase(filter.taps, kLogFloorBelowDelta * std::pow(10.0, -a / 20.0));
    }
    // The grid has >= 32 points per 1/taps (a stop-band lobe's width), so a lobe can peak up to
    // (pi / 64)^2 / 2 = 0.011 dB above the grid's largest value: ask for 0.05 dB more.
    filter.figures = MeasureFilter(filter.taps, m, p, s);
    if (filter.figures.stopband_attenuation_db >= a + 0.05) break;
    if (taps >= give_up) {
      throw ConfigError("synthesis option chain.stopband_attenuation_db = " + std::to_string(a) +
                        ": the filter design reaches only " +
                        std::to_string(filter.figures.stopband_attenuation_db) +
                        " dB; ask for less attenuation or a wider transition band");
    }
    taps += 2;
  }
  filter.lead =
      chain.phase == AdcFilterPhase::kLinear ? (static_cast<int>(filter.taps.size()) - 1) / 2 : 0;
  return filter;
}

}  // namespace bouncecal::audio
