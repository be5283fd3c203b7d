#ifndef BOUNCECAL_CALIBRATE_SRC_FIT_PROBLEM_H_
#define BOUNCECAL_CALIBRATE_SRC_FIT_PROBLEM_H_

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/option_error.h"

namespace bouncecal::calibrate::internal {

// How one measured sequence is simulated and compared: the release height of its drops and which
// measured impact the first simulated impact stands for (0 with a known drop height, 1 when the
// drop starts from the apex of the first measured flight).
struct SequencePlan {
  std::string source;
  std::filesystem::path path;  // the file the sequence came from
  std::vector<TimedImpact> impacts;
  RestitutionAnalysis measured;
  double release_height_m = 0;
  bool known_drop_height = true;
  // One-sigma uncertainty of a known drop height, m, and which height measurement it is: plans
  // of one group share one measured height (its error moves them together), different groups
  // were measured apart (independent errors).
  double drop_height_uncertainty_m = 0;
  int drop_height_group = 0;
  int first_matched_impact = 0;
  int impacts_needed = 0;  // simulated impacts the objective compares
  // The energy losses this recording's eta-bar averages under kMeanEnergyLoss: FitOptions::first_n,
  // or all the recording gives when fewer and first_n was not chosen (first_n_given).
  int first_n = 0;
  double max_time_s = 0;
  // Added to the timing variance of eta-bar under kMeanEnergyLoss: the per-impact scatter the
  // uncertainty model found (tau^2 / n), so a joint fit weights recordings by what they are
  // worth rather than by their onset timing alone. 0 in the first pass.
  double extra_variance = 0;
};

// The energy losses a plan's eta-bar averages: its own count under kMeanEnergyLoss, first_n
// under the other objectives (which report eta-bar but do not fit it).
inline int EtaBarCount(const SequencePlan& plan, const FitOptions& options) {
  return plan.first_n > 0 ? plan.first_n : options.first_n;
}

// The refusal of a recording whose sequence gives `available` energy losses where `first_n` are
// needed, naming what would help.
OptionError TooFewEnergyLosses(const SequencePlan& plan, int available, int first_n);

// Builds the plan. Throws ConfigError when the sequence is too short for the objective (under
// kMeanEnergyLoss: fewer energy losses than a chosen first_n, or none), and when
// the first measured rebound rose higher than the given drop height (a wrong height, or the
// first impact was missed): no restitution above 1 is ever fitted.
SequencePlan MakePlan(const MeasuredSequence& sequence, const FitOptions& options,
                      std::optional<double> drop_height_m);

// The measured incoming speed of impact `impact` (0-based) of the plan's recording: sqrt(2 g h0)
// for the first impact from the release height, g dt / 2 from the flight before it otherwise.
double IncomingSpeedMps(const SequencePlan& plan, int impact, double gravity_mps2);

// The indices into plan.measured.energy_loss of the impacts the objective depends on: those whose
// incoming and outgoing flights are both simulated and compared (the first first_n under
// kMeanEnergyLoss). The simulated energy_loss of a SimulatedSequence has the same indices.
std::vector<size_t> UsedEnergyLossEntries(const SequencePlan& plan);

// The fitted parameters in the optimiser's coordinates (log where the range says so).
class ParameterMap {
 public:
  ParameterMap(const FitOptions& options);
  size_t size() const { return names_.size(); }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<ParameterRange>& ranges() const { return ranges_; }
  std::vector<double> LowerBounds() const;
  std::vector<double> UpperBounds() const;
  std::vector<double> StartPoint(const dem::ContactLawConfig& law) const;
  // The law with the fitted parameters set from optimiser coordinates.
  dem::ContactLawConfig Apply(const dem::ContactLawConfig& law, std::span<const double> x) const;
  double Value(size_t i, double x) const;

 private:
  std::vector<std::string> names_;
  std::vector<ParameterRange> ranges_;
};

// One simulated sequence at a parameter set, reduced to what the objectives compare.
struct SimulatedSequence {
  std::vector<double> onsets_s;  // from the release
  std::vector<double> intervals_s;
  std::vector<double> energy_loss;  // aligned with the measured energy_loss entries
  double first_restitution = 0;
};

SimulatedSequence SimulateSequence(const dem::ContactLawConfig& law, const SequencePlan& plan,
                                   const FitOptions& options,
                                   std::optional<dem::Integrator> integrator_override = {});

// What one sequence contributes to the objective: chi-square = sum ((model - data) / sigma)^2.
// kMeanEnergyLoss: one entry (eta-bar); kIntervals / kHeights: one per compared flight.
struct ObjectiveTerms {
  std::vector<double> model;
  std::vector<double> data;
  std::vector<double> sigma;
};
ObjectiveTerms Terms(const SequencePlan& plan, const SimulatedSequence& simulated,
                     const FitOptions& options);

// The chi-square share and the number of data it compares.
double SequenceResidual(const SequencePlan& plan, const SimulatedSequence& simulated,
                        const FitOptions& options, int* data_points = nullptr);

// eta-bar of the first n entries, padding with 1 (all energy lost) when the ball came to rest.
double MeanOfFirst(const std::vector<double>& energy_loss, int n);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_FIT_PROBLEM_H_
