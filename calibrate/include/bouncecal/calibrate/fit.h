#ifndef BOUNCECAL_CALIBRATE_FIT_H_
#define BOUNCECAL_CALIBRATE_FIT_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bouncecal/calibrate/impact_times.h"
#include "bouncecal/calibrate/minimizer.h"
#include "bouncecal/calibrate/restitution.h"
#include "bouncecal/calibrate/uncertainty.h"
#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// What the simulated drops must reproduce. Every objective is a chi-square: squared residuals
// divided by the variance propagated from the onset-timing uncertainties, summed over the
// recordings fitted jointly, so residuals are comparable across objectives' recordings and feed
// the information criteria of CompareLaws.
//  - kMeanEnergyLoss: eta-bar over the first N impacts (the paper's method: N = 3; later impacts
//    carry two orders of magnitude less energy). One datum per recording.
//  - kIntervals: every measured flight interval, weighted by 1/sigma^2 of the interval (sigma^2 =
//    sum of its two onsets' variances). Neighbouring intervals share an onset; that correlation
//    is neglected, which slightly under-weights the late, noisy intervals' agreement.
//  - kHeights: bounce heights g dt^2 / 8, weighted the same way; stresses the first bounces.
enum class FitObjective { kMeanEnergyLoss, kIntervals, kHeights };
std::string_view ToString(FitObjective objective);
// "mean-energy-loss", "intervals", "heights"; throws ConfigError listing them otherwise.
FitObjective FitObjectiveFromString(std::string_view name);

// The search range of one fitted parameter. Parameters spanning orders of magnitude (stiffness,
// dissipative time) are searched in log space so the optimiser's steps are relative.
struct ParameterRange {
  double lower = 0;
  double upper = 1;
  bool log_scale = false;
};

// The dissipative parameters of a law (what a drop constrains; dem::ParameterRole): not the
// elastic ones that set only the contact duration (stiffness_n_per_m, effective_modulus_pa), nor
// the opt-in ones (the plastic law's plastic_flow_overlap_m; add them with fitted_parameters /
// --fit).
std::vector<std::string> DefaultFittedParameters(dem::ContactLawKind kind);
// The default search range of a parameter for the law `config`: its ParameterSpec's fit range
// (gamma_n [0, 0.98]; the plastic unloading stiffness [k1, 1e4 k1]; the Hertz dissipative time
// [1e-9, 1e-4] s in log space), scaled by the parameter it is relative to. Throws ConfigError for
// a name the law does not have.
ParameterRange DefaultParameterRange(const dem::ContactLawConfig& config, std::string_view name);

// The uncertainty model is described in uncertainty.h (and docs/calibration.md); it draws no
// random numbers, so its intervals do not depend on a seed or on the thread count.
struct UncertaintyOptions {
  double confidence_level = 0.95;
  // Threads for CompareLaws (one law per thread); results do not depend on it.
  int threads = 2;
  // One-sigma uncertainty of the drop height, propagated into the intervals (h0 sets dt_0, so it
  // enters eta_1 directly); 0 treats h0 as exact. Requires a given drop height.
  double drop_height_uncertainty_m = 0;
};

// The ball simulated when none is given and the result does not depend on it (the paper's 1 cm
// steel ball): see ResultDependsOnBall.
dem::Ball ReferenceBall();

// The energy losses at least one recording must give when first_n was not chosen. One is not
// enough: its per-impact scatter cannot be estimated, so the interval of one recording would hold
// timing noise alone and miss a ball whose impacts scatter by a few per cent.
inline constexpr int kFewestDefaultFirstN = 2;

struct FitOptions {
  // The simulated drop set-up, declared once for the fit, sweep and compare (dem::DropOptions):
  //  - drop.law: the law, its fixed parameters and the start values of the fitted ones;
  //  - drop.ball: the ball simulated, the experiment's when ball_given, else ReferenceBall();
  //  - drop.drop_height_m: the release height when drop_height_given, else unused;
  //  - gravity, drag, integrator, time step or steps per contact, step grid and the drop engine's
  //    other settings as given;
  //  - max_impacts and max_time_s are set for each recording from its measured impacts, and no
  //    trajectory is recorded.
  dem::DropOptions drop;
  // Whether the experiment's ball and release height were given. The fit never assumes a geometry
  // nobody gave, yet every drop needs a ball and a height, so the two are flags beside the one
  // drop set-up rather than optional copies of its fields (two places for one quantity) or
  // optionals inside dem::DropOptions (every other caller of the drop engine would have to fill
  // them). Fit refuses a drop.ball other than ReferenceBall() or a drop.drop_height_m other than
  // dem::DropOptions' default without its flag, so a forgotten flag is an error, never a silently
  // ignored value. Read them through GivenBall() and GivenDropHeightM().
  //  - Ball not given: Fit accepts it only when the result does not depend on it
  //    (ResultDependsOnBall); the drops then use ReferenceBall() and the summary says so.
  //  - Height not given (the default: an experiment's geometry is never assumed): e_1 and eta_1
  //    are not computed, and each simulation starts from rest at the apex of the first measured
  //    flight (g dt_1^2 / 8), matched to the measured impacts from the second one on. Given: a
  //    first rebound higher than it is refused (ConfigError).
  bool ball_given = false;
  bool drop_height_given = false;
  std::string ball_preset;  // the preset name the ball came from, if any (recorded in the card)
  // Empty: DefaultFittedParameters(drop.law.kind).
  std::vector<std::string> fitted_parameters;
  // Overrides of DefaultParameterRange per parameter name.
  std::map<std::string, ParameterRange, std::less<>> ranges;

  FitObjective objective = FitObjective::kMeanEnergyLoss;
  int first_n = 3;  // impacts averaged by kMeanEnergyLoss
  // Whether first_n was chosen. Not chosen (the default 3), a recording whose sequence gives
  // fewer energy losses averages all it gives (SequenceFit::first_n), and a warning names it: a
  // lossy ball's short sequence gets a wider interval (fewer impacts to show its scatter) instead
  // of a refusal, and one short recording among several no longer refuses them all. At least one
  // recording must give kFewestDefaultFirstN. Chosen, a recording that gives fewer is refused
  // (ConfigError naming the count and what to do). Fit refuses a first_n other than 3 without the
  // flag, as it does the ball's and the height's.
  bool first_n_given = false;
  // Intervals fitted by kIntervals/kHeights per recording (0: all). Late intervals of a long
  // chatter add little information and cost simulated time.
  int max_intervals = 0;

  // global_evaluations < 0 picks automatically: no global stage for one parameter under
  // kMeanEnergyLoss (eta-bar is monotone in the damping of every law here, so the squared
  // misfit is unimodal), otherwise DIRECT-L with 12 evaluations per fitted parameter before the
  // local polish (interval objectives of two-parameter, speed-dependent laws can have valleys).
  MinimizerOptions minimizer = [] {
    MinimizerOptions options;
    options.global_evaluations = -1;
    options.parameter_tolerance = 1e-5;
    options.max_evaluations = 200;
    return options;
  }();
  UncertaintyOptions uncertainty;
  // Run the analytic check of AnalyticCheck (two extra drops).
  bool analytic_check = true;
  // When set, the law's elastic parameter (k_n, E*) is the one that makes the simulated contact
  // last this long (s) with the fitted damping at the fit's first impact speed
  // (WithContactDuration). The duration depends on the damping (walton-braun's two branches), so
  // Fit derives the stiffness from the starting damping, fits, derives it again from the fitted
  // damping and fits once more; the damping barely depends on k_n (gravity during contact), so
  // the duration then holds to ~1e-3. Needs the ball (its mass sets the stiffness).
  std::optional<double> contact_duration_s;

  // drop.ball when ball_given, else nothing.
  std::optional<dem::Ball> GivenBall() const;
  // drop.drop_height_m when drop_height_given, else nothing.
  std::optional<double> GivenDropHeightM() const;
  // The numeric settings (height, gravity, first_n, max_intervals, max_evaluations,
  // confidence_level, threads, drop_height_uncertainty_m) in range; throws OptionError naming
  // the field. Fit checks them too, with the law and the ball; a front end calls this before it
  // reads any input.
  void ValidateSettings() const;
};

struct FittedParameter {
  std::string name;
  std::string unit;
  double value = 0;
  ParameterRange range;
  bool at_bound = false;  // within 1e-3 of the range width of a bound: the range may be too tight
  // The interval at UncertaintyOptions::confidence_level of the uncertainty model (uncertainty.h);
  // empty when the model does not apply (parameters not separately determined).
  std::optional<std::pair<double, double>> confidence_interval;
  bool interval_clipped = false;  // the interval reached the search range and was cut there
  double standard_error = 0;      // linearised, in the parameter's unit
};

// The fitted damping parameter beside the value the law's closed form gives for the measured
// eta-bar. walton-braun: the paper's eta = 2 gamma / (1 + gamma). Every other law with one fitted
// parameter: 1 - e^2 of its gravity-free closed-form restitution (dem::ClosedFormRestitutionOf)
// averaged over the measured incoming speeds of the impacts in eta-bar (speed-dependent laws
// differ from impact to impact), inverted over the parameter's search range by bisection. Not
// applicable with several fitted parameters, or where the closed form cannot reach eta-bar.
struct AnalyticCheck {
  bool applicable = false;
  std::string parameter;        // the fitted parameter checked, e.g. "gamma_n"
  std::string formula;          // "eta = 2 gamma / (1 + gamma)", or which law's closed form
  double energy_loss_mean = 0;  // measured eta-bar (first N), averaged over the recordings
  double energy_loss_mean_uncertainty = 0;
  double formula_value = 0;  // the parameter the closed form gives for eta-bar
  double fitted_value = 0;
  double difference = 0;  // fitted - formula, in the parameter's unit
  // Measured, not tabulated, each converted to the parameter: walton-braun's through d eta /
  // d gamma = 2 / (1 + gamma)^2 (its errors are ~1e-4 small), the other laws' through the closed
  // form's inverse (an approximate closed form can be off by per cent, beyond first order):
  //  - time-step error: the fitted law simulated without drag with the chosen integrator and step
  //    against the reference path: exact (event-driven) where the law has one, else RK4 at eight
  //    times the steps per contact;
  //  - model error of the closed form: the reference drop against it (gravity during contact,
  //    onsets vs the centre of the contact, impact speeds from flight times);
  //  - air drag (with drag on): the chosen-step drop with drag against the same drop without it.
  double energy_loss_mean_chosen_step = 0;  // as fitted (drag included when on)
  double energy_loss_mean_exact = 0;        // reference path, no drag
  std::string reference_integrator;         // "exact", or "rk4" where the law has no exact path
  double energy_loss_formula = 0;           // the closed form's eta-bar at the fitted value
  double time_step_error = 0;
  double model_error = 0;  // gravity during contact
  double drag_error = 0;   // 0 without drag
  // |time-step| + |model| + |drag| + 2 sigma of formula_value (sigma from the uncertainty model's
  // eta-bar uncertainty) + the optimiser's tolerance (1e-4 of the search range).
  double explained = 0;
  bool warning = false;
  std::string message;  // one sentence; a warning names the next step
};

struct SequenceFit {
  std::string source;
  std::filesystem::path path;  // the file it came from
  // The release height this sequence's drops started from; unset when unknown (the drops then
  // started from the apex of its first measured flight).
  std::optional<double> drop_height_m;
  RestitutionAnalysis measured;
  // The energy losses its eta-bar averages under kMeanEnergyLoss (FitSummary::first_n, or all the
  // recording gives when fewer); 0 under the other objectives.
  int first_n = 0;
  std::vector<double> simulated_onsets_s;  // at the fit, on the measured time axis
  // The fitted drop analysed as the measurement is. Its impact_index numbers the measured
  // impacts, as measured.impact_index does: without a drop height its first entry is 1, the
  // measured impact the simulation's first impact stands for.
  RestitutionAnalysis simulated;
  double residual = 0;  // this recording's chi-square share
};

struct FitSummary {
  dem::ContactLawConfig law;  // fixed + fitted values
  std::vector<FittedParameter> parameters;
  FitObjective objective = FitObjective::kMeanEnergyLoss;
  // The impacts kMeanEnergyLoss averages per recording, FitOptions::first_n; a recording that gave
  // fewer averaged all it gave (SequenceFit::first_n, FitOptions::first_n_given).
  int first_n = 3;
  double residual = 0;  // chi-square at the fit
  int data_points = 0;
  int degrees_of_freedom = 0;     // data_points - fitted parameters (may be <= 0)
  double reduced_chi_square = 0;  // residual / dof when dof > 0, else 0
  // Gaussian likelihood with the stated uncertainties: -2 ln L = chi^2 + const.
  double aic = 0;  // chi^2 + 2 k
  double bic = 0;  // chi^2 + k ln n
  MinimizerStop stop = MinimizerStop::kFailure;
  std::string stop_message;
  int evaluations = 0;  // drop simulations in the main fit (each covers every recording)
  double fit_time_s = 0;
  double total_time_s = 0;             // fit + check + uncertainty
  std::vector<SequenceFit> sequences;  // the distinct ones
  AnalyticCheck check;
  // Restitution and energy loss the fitted law implies for the first impact from the drop
  // height (speed-dependent laws: at that speed), from the simulated drop.
  double implied_restitution = 0;
  double implied_energy_loss = 0;
  // What the law's elastic parameter means for the simulated ball: its gravity-free closed-form
  // contact duration (calibrate::ContactDurationS) at the first simulated impact's speed
  // sqrt(2 g h) from the release height; unset where the law has no closed form. It sets the DEM
  // time step of the drops and of every scene built on the card.
  std::optional<double> contact_duration_s;
  double contact_speed_mps = 0;
  UncertaintySummary uncertainty;
  ModelAdequacy adequacy;
  // Whether the ball was given; when not, the drops used ReferenceBall().
  bool ball_given = false;
  // Everything the user should act on, one sentence each, each naming the next step: duplicate
  // recordings, a parameter at its range's edge, a trend with impact speed, the analytic check.
  std::vector<std::string> warnings;
};

// True when the fitted parameters depend on the ball's size or mass: air drag, and the laws whose
// parameters say so (dem::BallDependence): those with a scale of their own, such as the Hertz
// laws, whose restitution depends on impact speed through mass and radius, and Luding's plastic
// flow.
// The hysteretic, plastic (1986) and dashpot laws lose a fixed fraction of energy per impact
// whatever the ball; the ball then sets only the contact duration, which moves gamma_n by less
// than 1e-4 through gravity during contact (the analytic check measures it).
bool ResultDependsOnBall(const FitOptions& options);
// Why, as a phrase ("air drag", "the hertz-viscoelastic law", "the walton-braun-plastic law's
// plastic_flow_overlap_m"), or empty.
std::string WhyResultDependsOnBall(const FitOptions& options);

// Fits the law's parameters so single-ball DEM drops (dem::SimulateDrop) reproduce the measured
// sequences jointly. Sequences with identical impact times (the same recording given twice) are
// fitted once, with a warning. Throws ConfigError for bad options (named, with the valid range),
// for a missing ball where the result depends on it, when a sequence has too few impacts for the
// objective and when a first rebound rose above the given drop height.
FitSummary Fit(const std::vector<MeasuredSequence>& sequences, const FitOptions& options = {});

// CompareLaws fits each law with the same options and ranks them.
struct LawComparison {
  std::vector<FitSummary> fits;  // sorted by BIC, best first
  // One line when the laws were fitted on another objective than asked, so that every law keeps a
  // degree of freedom (see CompareLaws); empty otherwise.
  std::string objective_note;
  // One line per law whose chi^2 lies outside the central 99 % of the chi-square distribution
  // for its degrees of freedom, naming the numbers and the next step.
  std::vector<std::string> warnings;
};

// How far a ranking can be trusted: a law's chi^2 should be a draw from the chi-square
// distribution with its dof when its misfit is the stated timing noise. Outside the central
// `kGoodnessOfFitLevel` of it the uncertainties do not describe the misfit, and BIC differences
// (which are chi^2 differences) are off by about chi^2/dof.
inline constexpr double kGoodnessOfFitLevel = 0.99;
// The warning for one fit, or empty when its chi^2 lies inside the central kGoodnessOfFitLevel
// (or it has no degree of freedom).
std::string GoodnessOfFitWarning(const FitSummary& fit);
// Ranked by BIC (Schwarz 1978) rather than AIC: the question is which law generated the data
// (is one constant gamma enough?), and BIC is consistent for that as the number of intervals
// grows, while AIC (also reported) targets prediction and keeps over-parameterised laws. Laws
// without dissipative parameters (hertz) are skipped. Each law takes the parameters of
// options.drop.law it has by name (so options.drop.law may carry, e.g., both stiffness_n_per_m and
// effective_modulus_pa); the rest take their defaults. Runs the laws on
// options.uncertainty.threads.
// A ranking needs a degree of freedom for every law (more data than the law's fitted parameters):
// with fewer, each law fits the data exactly (chi^2 ~ 1e-12) and BIC ranks by parameter count
// alone. Then, under kMeanEnergyLoss (one datum per recording) when `objective_given` is false,
// the laws are fitted on every flight interval (kIntervals) and objective_note says so; otherwise
// ConfigError naming the numbers and what to do.
LawComparison CompareLaws(const std::vector<MeasuredSequence>& sequences,
                          const std::vector<dem::ContactLawKind>& laws, const FitOptions& options,
                          bool objective_given = false);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_FIT_H_
