#ifndef BOUNCECAL_CALIBRATE_RESTITUTION_H_
#define BOUNCECAL_CALIBRATE_RESTITUTION_H_

#include <optional>
#include <vector>

namespace bouncecal::calibrate {

// Ballistic-flight analysis of one bounce sequence (docs/physics.md section 1): the flight
// between impacts k and k+1 lasts dt_k, so the ball left impact k at g dt_k / 2 and rose to
// g dt_k^2 / 8; e_k = dt_k / dt_{k-1} and eta_k = 1 - e_k^2. Contact time and drag are neglected.
struct RestitutionOptions {
  double gravity_mps2 = 9.81;
  // When set, the flight that would have preceded impact 1, dt_0 = 2 sqrt(2 h0 / g), gives e and
  // eta of the first impact too (the paper's convention).
  std::optional<double> drop_height_m;
  // One-sigma uncertainty of drop_height_m, m: e_1 = dt_1 / dt_0 moves by -e_1 / (2 h0) per metre
  // of h0, independently of the timing, so it widens e_1, eta_1 and the mean that includes them.
  double drop_height_uncertainty_m = 0;
  // Number of impacts averaged in energy_loss_mean_first_n (the paper uses 3).
  int first_n = 3;
};

// An impact time with its one-sigma timing uncertainty.
struct TimedImpact {
  double onset_s = 0;
  double uncertainty_s = 0;
  // One sigma of the flight that ends at this impact beyond its two onsets' own: a shift common
  // to every earlier onset of the sequence (Impact::incoming_flight_uncertainty_s), which moves
  // this flight alone. 0 on a sequence's first impact.
  double incoming_flight_uncertainty_s = 0;
};

struct RestitutionAnalysis {
  // Flights between consecutive impacts: intervals_s[j] = onset[j+1] - onset[j].
  std::vector<double> intervals_s;
  std::vector<double> interval_uncertainty_s;
  std::vector<double> bounce_height_m;  // g dt^2 / 8, one per interval
  std::vector<double> bounce_height_uncertainty_m;
  // One entry per impact that has both an incoming and an outgoing flight. impact_index is the
  // 0-based index into the onsets: starting at 0 with a drop height, otherwise at 1.
  std::vector<int> impact_index;
  std::vector<double> restitution;
  std::vector<double> restitution_uncertainty;
  std::vector<double> energy_loss;
  std::vector<double> energy_loss_uncertainty;
  // Mean of the first first_n energy_loss entries; empty when there are fewer than first_n.
  std::optional<double> energy_loss_mean_first_n;
  std::optional<double> energy_loss_mean_first_n_uncertainty;
};

// Throws ConfigError for non-finite or non-increasing onsets, a non-positive gravity, drop
// height or first_n. Uncertainties are propagated to first order from independent onset errors
// (an onset enters two intervals with opposite signs, so the correlation is kept) and independent
// incoming-flight errors (every earlier onset shifted together).
RestitutionAnalysis AnalyzeRestitution(const std::vector<TimedImpact>& impacts,
                                       const RestitutionOptions& options = {});

// dt_0 = 2 sqrt(2 h0 / g): the flight time of a drop from rest at h0 back to the floor.
double DropFlightTime(double drop_height_m, double gravity_mps2);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_RESTITUTION_H_
