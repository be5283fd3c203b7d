#include "bouncecal/calibrate/restitution.h"

#include <cmath>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// sigma of a quantity from its gradient with respect to the onsets, onsets independent, and of
// the shifts common to the onsets before an impact with an incoming-flight uncertainty, which
// move the quantity by the sum of those onsets' gradients.
double PropagatedSigma(const std::vector<double>& gradient,
                       const std::vector<TimedImpact>& impacts) {
  double variance = 0;
  double earlier_gradient = 0;
  for (size_t i = 0; i < gradient.size(); ++i) {
    const double shift_term = earlier_gradient * impacts[i].incoming_flight_uncertainty_s;
    const double term = gradient[i] * impacts[i].uncertainty_s;
    variance += term * term + shift_term * shift_term;
    earlier_gradient += gradient[i];
  }
  return std::sqrt(variance);
}

void Validate(const std::vector<TimedImpact>& impacts, const RestitutionOptions& options) {
  if (!(options.gravity_mps2 > 0) || !std::isfinite(options.gravity_mps2)) {
    throw ConfigError("gravity must be a positive number of m/s^2, got " +
                      std::to_string(options.gravity_mps2));
  }
  if (options.drop_height_m &&
      (!(*options.drop_height_m > 0) || !std::isfinite(*options.drop_height_m))) {
    throw ConfigError("drop height must be a positive number of metres, got " +
                      std::to_string(*options.drop_height_m));
  }
  if (!(options.drop_height_uncertainty_m >= 0) ||
      !std::isfinite(options.drop_height_uncertainty_m)) {
    throw ConfigError("drop height uncertainty must be >= 0 m, got " +
                      std::to_string(options.drop_height_uncertainty_m));
  }
  if (options.first_n < 1) {
    throw ConfigError("first N must be at least 1, got " + std::to_string(options.first_n));
  }
  for (size_t i = 0; i < impacts.size(); ++i) {
    const TimedImpact& impact = impacts[i];
    if (!std::isfinite(impact.onset_s) || !(impact.uncertainty_s >= 0) ||
        !std::isfinite(impact.uncertainty_s) || !(impact.incoming_flight_uncertainty_s >= 0) ||
        !std::isfinite(impact.incoming_flight_uncertainty_s)) {
      throw ConfigError("impact " + std::to_string(i + 1) +
                        " has a non-finite onset or a negative/non-finite uncertainty");
    }
    if (i > 0 && !(impacts[i].onset_s > impacts[i - 1].onset_s)) {
      throw ConfigError("impact times must increase strictly; impact " + std::to_string(i + 1) +
                        " is not later than impact " + std::to_string(i));
    }
  }
}

}  // namespace

double DropFlightTime(double drop_height_m, double gravity_mps2) {
  return 2.0 * std::sqrt(2.0 * drop_height_m / gravity_mps2);
}

RestitutionAnalysis AnalyzeRestitution(const std::vector<TimedImpact>& impacts,
                                       const RestitutionOptions& options) {
  Validate(impacts, options);
  RestitutionAnalysis result;
  const double g = options.gravity_mps2;
  const size_t n = impacts.size();
  for (size_t j = 0; j + 1 < n; ++j) {
    const double dt = impacts[j + 1].onset_s - impacts[j].onset_s;
    const double sigma = std::hypot(impacts[j].uncertainty_s, impacts[j + 1].uncertainty_s,
                                    impacts[j + 1].incoming_flight_uncertainty_s);
    result.intervals_s.push_back(dt);
    result.interval_uncertainty_s.push_back(sigma);
    result.bounce_height_m.push_back(g * dt * dt / 8.0);
    result.bounce_height_uncertainty_m.push_back(g * dt * sigma / 4.0);
  }

  // Each restitution entry keeps its gradient over the onsets so the mean's uncertainty is
  // propagated with the shared-onset correlations intact.
  std::vector<std::vector<double>> energy_loss_gradients;
  auto add_impact = [&](int impact, double incoming, double outgoing,
                        std::vector<double> gradient_of_e) {
    const double e = outgoing / incoming;
    const double eta = 1.0 - e * e;
    std::vector<double> gradient_of_eta(gradient_of_e.size());
    for (size_t i = 0; i < gradient_of_e.size(); ++i)
      gradient_of_eta[i] = -2.0 * e * gradient_of_e[i];
    result.impact_index.push_back(impact);
    result.restitution.push_back(e);
    result.restitution_uncertainty.push_back(PropagatedSigma(gradient_of_e, impacts));
    result.energy_loss.push_back(eta);
    result.energy_loss_uncertainty.push_back(PropagatedSigma(gradient_of_eta, impacts));
    energy_loss_gradients.push_back(std::move(gradient_of_eta));
  };

  // d eta_1 / d h0: e_1 = dt_1 / dt_0 with dt_0 ~ sqrt(h0), so d e_1 / d h0 = -e_1 / (2 h0) and
  // d eta_1 / d h0 = e_1^2 / h0. Zero without a height uncertainty.
  double first_energy_loss_height_sigma = 0;
  if (options.drop_height_m && n >= 2) {
    // dt_0 comes from h0, not from a measurement, so only t_1 and t_2 carry timing error.
    const double h0 = *options.drop_height_m;
    const double incoming = DropFlightTime(h0, g);
    std::vector<double> gradient(n, 0.0);
    gradient[0] = -1.0 / incoming;
    gradient[1] = 1.0 / incoming;
    add_impact(0, incoming, result.intervals_s[0], std::move(gradient));
    if (options.drop_height_uncertainty_m > 0) {
      const double e = result.restitution.front();
      const double height_sigma_e = e / (2.0 * h0) * options.drop_height_uncertainty_m;
      first_energy_loss_height_sigma = e * e / h0 * options.drop_height_uncertainty_m;
      result.restitution_uncertainty.front() =
          std::hypot(result.restitution_uncertainty.front(), height_sigma_e);
      result.energy_loss_uncertainty.front() =
          std::hypot(result.energy_loss_uncertainty.front(), first_energy_loss_height_sigma);
    }
  }
  for (size_t k = 1; k + 1 < n; ++k) {
    const double incoming = result.intervals_s[k - 1];  // t_k - t_{k-1}
    const double outgoing = result.intervals_s[k];      // t_{k+1} - t_k
    const double e = outgoing / incoming;
    std::vector<double> gradient(n, 0.0);
    gradient[k + 1] = 1.0 / incoming;
    gradient[k] = -(1.0 + e) / incoming;
    gradient[k - 1] = e / incoming;
    add_impact(static_cast<int>(k), incoming, outgoing, std::move(gradient));
  }

  const size_t first_n = static_cast<size_t>(options.first_n);
  if (result.energy_loss.size() >= first_n) {
    double mean = 0;
    std::vector<double> gradient(n, 0.0);
    for (size_t j = 0; j < first_n; ++j) {
      mean += result.energy_loss[j] / first_n;
      for (size_t i = 0; i < n; ++i) gradient[i] += energy_loss_gradients[j][i] / first_n;
    }
    result.energy_loss_mean_first_n = mean;
    result.energy_loss_mean_first_n_uncertainty =
        std::hypot(PropagatedSigma(gradient, impacts), first_energy_loss_height_sigma / first_n);
  }
  return result;
}

}  // namespace bouncecal::calibrate
