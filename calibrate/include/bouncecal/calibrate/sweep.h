#ifndef BOUNCECAL_CALIBRATE_SWEEP_H_
#define BOUNCECAL_CALIBRATE_SWEEP_H_

#include <optional>
#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// The paper's Fig. 6: simulated energy loss against one law parameter (gamma_n by default), next
// to the law's closed form at the first impact where it has one (ClosedFormEnergyLoss; for
// walton-braun the paper's eta = 2 gamma / (1 + gamma)).
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
  // ClosedFormEnergyLoss at the first impact's speed: compare it with first_contact_energy_loss
  // (the closed forms leave out gravity during the contact). Unset for a law without one.
  std::optional<double> analytic_energy_loss;
  int impacts = 0;
  double time_step_s = 0;
};

struct SweepSummary {
  std::vector<SweepPoint> points;
  // Speed of the first impact, the same for every value: the fall from the drop height does not
  // depend on the law. 0 when no drop reached the plane.
  double first_impact_speed_mps = 0;
  double time_s = 0;
};

// Parses "lo:hi:step" (inclusive of hi within half a step) or "a,b,c". Throws ConfigError.
std::vector<double> ParseValueList(const std::string& text);

// Throws ConfigError for an unknown parameter, a value outside its range, or first_n < 1.
SweepSummary Sweep(const SweepOptions& options);

// 1 - e^2 of the law's gravity-free closed-form restitution (dem::ClosedFormRestitutionOf) for
// `ball` on a plane at impact_speed_mps, or nothing where the law has none. Speed-dependent laws
// (thornton, hertz-viscoelastic, Luding's plastic flow) depend on the speed; the others do not.
// hertz-viscoelastic's is Ramirez et al.'s second-order series, good at small damping only (at
// dissipative_time_s = 3e-6 s it is 0.028 below the simulated first-contact eta of 0.627).
// Throws ConfigError for an invalid law.
std::optional<double> ClosedFormEnergyLoss(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                           double impact_speed_mps);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_SWEEP_H_
