#ifndef BOUNCECAL_CALIBRATE_SWEEP_H_
#define BOUNCECAL_CALIBRATE_SWEEP_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// The paper's Fig. 6: simulated energy loss against one law parameter (gamma_n by default), next
// to the closed form eta = 2 gamma / (1 + gamma) where it exists (walton-braun).
struct SweepOptions {
  // The simulated drop: its law is the kind and the fixed parameters, `parameter` takes each of
  // `values` in turn; every other field (ball, height, gravity, drag, integrator, step) is used
  // as given. max_impacts is set to first_n + 1.
  dem::DropOptions drop;
  std::string parameter = "gamma_n";
  std::vector<double> values = {0.1, 0.3, 0.5, 0.7, 0.9};
  int first_n = 3;
};

struct SweepPoint {
  double value = 0;
  // From the simulated onsets exactly as a recording is analysed (flight-time ratios, dt_0 from
  // the drop height): what the paper plots.
  double first_energy_loss = 0;
  double energy_loss_mean_first_n = 0;
  // 1 - (v_out / v_in)^2 of the first contact itself (no flight-time estimator).
  double first_contact_energy_loss = 0;
  std::optional<double> analytic_energy_loss;  // 2 gamma / (1 + gamma), walton-braun only
  int impacts = 0;
  double time_step_s = 0;
};

struct SweepSummary {
  std::vector<SweepPoint> points;
  double time_s = 0;
};

// Parses "lo:hi:step" (inclusive of hi within half a step) or "a,b,c". Throws ConfigError.
std::vector<double> ParseValueList(const std::string& text);

// Throws ConfigError for an unknown parameter, a value outside its range, or first_n < 1.
SweepSummary Sweep(const SweepOptions& options);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_SWEEP_H_
