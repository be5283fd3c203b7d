#include "bouncecal/calibrate/fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// A measured sequence taken straight from a simulated drop: onsets plus Gaussian timing noise of
// sigma_s (seeded), each onset then carrying sigma_s as its stated uncertainty. A constant offset
// stands in for the recording's unknown start (it must cancel).
MeasuredSequence SimulatedRecording(const dem::ContactLawConfig& law, int impacts, double sigma_s,
                                    std::uint64_t seed, double drop_height_m = 0.2,
                                    dem::Integrator integrator = dem::Integrator::kExact) {
  dem::DropOptions drop;
  drop.law = law;
  drop.drop_height_m = drop_height_m;
  drop.integrator = integrator;
  drop.max_impacts = impacts;
  const auto result = dem::SimulateDrop(drop);
  std::mt19937_64 random(seed);
  std::normal_distribution<double> noise(0.0, sigma_s);
  MeasuredSequence sequence;
  sequence.source = "simulated";
  for (const auto& impact : result.impacts)
    sequence.impacts.push_back({1.234 + impact.time_s + (sigma_s > 0 ? noise(random) : 0.0),
                                sigma_s > 0 ? sigma_s : 1e-6});
  return sequence;
}

dem::ContactLawConfig WaltonBraun(double gamma) {
  return {dem::ContactLawKind::kWaltonBraun, {{"gamma_n", gamma}}};
}

FitOptions QuickOptions() {
  FitOptions options;
  options.uncertainty.bootstrap_samples = 0;
  return options;
}

TEST(FitOptions, DefaultsAreValidAndFitTheDefaultSetUp) {
  const FitOptions options;
  EXPECT_NO_THROW(options.law.Validate());
  EXPECT_EQ(options.objective, FitObjective::kMeanEnergyLoss);
  EXPECT_EQ(options.first_n, 3);
  ASSERT_TRUE(options.drop_height_m.has_value());
  EXPECT_DOUBLE_EQ(*options.drop_height_m, 0.2);
  EXPECT_EQ(DefaultFittedParameters(options.law.kind), std::vector<std::string>{"gamma_n"});
}

TEST(Fit, RecoversGammaFromANoiselessDropSimulatedWithTheSameIntegrator) {
  // Same integrator and step on both sides, so the only error is the optimiser's: xtol 1e-5 of
  // the [0, 0.98] range plus the flatness of chi^2 near its zero; 1e-4 covers both.
  auto options = QuickOptions();
  const auto recording =
      SimulatedRecording(WaltonBraun(0.4), 8, 0, 1, 0.2, dem::Integrator::kVelocityVerlet);
  const auto summary = Fit({recording}, options);
  ASSERT_EQ(summary.parameters.size(), 1u);
  EXPECT_NEAR(summary.parameters[0].value, 0.4, 1e-4);
  EXPECT_TRUE(IsConverged(summary.stop)) << summary.stop_message;
  EXPECT_GT(summary.evaluations, 0);
  EXPECT_FALSE(summary.parameters[0].at_bound);
}

TEST(Fit, IntervalsObjectiveWithTimingNoiseCoversTheTruthWithItsInterval) {
  auto options = QuickOptions();
  options.objective = FitObjective::kIntervals;
  options.uncertainty.bootstrap_samples = 24;
  // Generated with the fit's own integrator and step, so only the timing noise separates data
  // and model (the verlet-vs-exact bias, ~5e-4 in gamma at 50 steps per contact, is the analytic
  // check's business and would dominate a 20 us noise interval).
  const auto recording =
      SimulatedRecording(WaltonBraun(0.45), 14, 20e-6, 7, 0.2, dem::Integrator::kVelocityVerlet);
  const auto summary = Fit({recording}, options);
  const auto& gamma = summary.parameters[0];
  ASSERT_TRUE(gamma.confidence_interval.has_value());
  // 20 us onset noise over 13 intervals pins gamma to ~1e-3; the 95 % interval must contain the
  // truth (this seed is not special: the check holds for 95 % of seeds by construction, and the
  // seed is fixed so the test is deterministic).
  EXPECT_LE(gamma.confidence_interval->first, 0.45);
  EXPECT_GE(gamma.confidence_interval->second, 0.45);
  EXPECT_NEAR(gamma.value, 0.45, 0.01);
  EXPECT_GT(gamma.bootstrap_std, 0);
  EXPECT_EQ(summary.data_points, 13);
  // chi^2 of a correct model with correct sigmas is ~ dof (13 - 1) with sd sqrt(24); 3 sd margin.
  EXPECT_LT(summary.residual, 12 + 3 * std::sqrt(24.0));
}

TEST(Fit, UnknownDropHeightStartsFromTheFirstMeasuredApex) {
  auto options = QuickOptions();
  options.drop_height_m.reset();
  options.objective = FitObjective::kIntervals;
  // The recording was dropped from 0.35 m, which the fit is not told.
  const auto recording = SimulatedRecording(WaltonBraun(0.3), 10, 5e-6, 3, 0.35);
  const auto summary = Fit({recording}, options);
  // 5 us noise on ~0.2 s flights: gamma to a few 1e-4; 3e-3 allows the exact/verlet difference
  // between the synthetic data and the fit's drops (measured ~1e-3 at the default step).
  EXPECT_NEAR(summary.parameters[0].value, 0.3, 3e-3);
}

TEST(Fit, JointFitOfTwoRecordingsLandsBetweenThem) {
  auto options = QuickOptions();
  const auto a = SimulatedRecording(WaltonBraun(0.38), 6, 10e-6, 11);
  const auto b = SimulatedRecording(WaltonBraun(0.42), 6, 10e-6, 12);
  const double joint = Fit({a, b}, options).parameters[0].value;
  EXPECT_GT(joint, Fit({a}, options).parameters[0].value);
  EXPECT_LT(joint, Fit({b}, options).parameters[0].value);
}

TEST(Fit, AnalyticCheckExplainsTheDifferenceForTheMeanEnergyLossFit) {
  auto options = QuickOptions();
  const auto recording = SimulatedRecording(WaltonBraun(0.408), 6, 10e-6, 5);
  const auto summary = Fit({recording}, options);
  const auto& check = summary.check;
  ASSERT_TRUE(check.applicable);
  EXPECT_FALSE(check.warning) << check.message;
  // The fit matches eta-bar, so the gap to the formula must be what the measured time-step and
  // gravity errors predict, to first order in those errors (1e-3 of gamma).
  EXPECT_NEAR(check.difference, -(check.time_step_gamma_error + check.model_gamma_error), 1e-3);
  EXPECT_NEAR(check.gamma_n_formula, check.energy_loss_mean / (2 - check.energy_loss_mean), 1e-12);
}

TEST(Fit, AnalyticCheckWarnsWhenOneGammaCannotDescribeTheImpacts) {
  // Speed-dependent data (Hertz viscoelastic: eta_k falls with k) fitted with one constant gamma
  // over every interval: eta-bar of the first three and the fitted gamma disagree beyond the
  // time-step error.
  auto options = QuickOptions();
  options.objective = FitObjective::kIntervals;
  const dem::ContactLawConfig hertz{dem::ContactLawKind::kHertzViscoelastic,
                                    {{"dissipative_time_s", 3e-6}}};
  const auto recording =
      SimulatedRecording(hertz, 25, 10e-6, 9, 0.2, dem::Integrator::kVelocityVerlet);
  const auto summary = Fit({recording}, options);
  EXPECT_TRUE(summary.check.warning) << summary.check.message;
}

TEST(Fit, RecoversTheHertzViscoelasticDissipativeTime) {
  auto options = QuickOptions();
  options.law = {dem::ContactLawKind::kHertzViscoelastic, {}};
  options.objective = FitObjective::kIntervals;
  const dem::ContactLawConfig truth{dem::ContactLawKind::kHertzViscoelastic,
                                    {{"dissipative_time_s", 3e-6}}};
  const auto recording =
      SimulatedRecording(truth, 15, 10e-6, 4, 0.2, dem::Integrator::kVelocityVerlet);
  const auto summary = Fit({recording}, options);
  ASSERT_EQ(summary.parameters[0].name, "dissipative_time_s");
  // Same integrator both sides; 10 us noise over 14 intervals: ~1 % on A. 3 % is 3 sigma.
  EXPECT_NEAR(summary.parameters[0].value, 3e-6, 0.03 * 3e-6);
}

TEST(CompareLaws, PrefersTheLawThatGeneratedTheData) {
  auto options = QuickOptions();
  options.objective = FitObjective::kIntervals;
  const dem::ContactLawConfig truth{dem::ContactLawKind::kHertzViscoelastic,
                                    {{"dissipative_time_s", 3e-6}}};
  const auto recording =
      SimulatedRecording(truth, 20, 10e-6, 21, 0.2, dem::Integrator::kVelocityVerlet);
  const auto comparison = CompareLaws(
      {recording}, {dem::ContactLawKind::kWaltonBraun, dem::ContactLawKind::kHertzViscoelastic},
      options);
  ASSERT_EQ(comparison.fits.size(), 2u);
  EXPECT_EQ(comparison.fits[0].law.kind, dem::ContactLawKind::kHertzViscoelastic);
  // Kass & Raftery: a BIC gap above 10 is very strong evidence.
  EXPECT_GT(comparison.fits[1].bic - comparison.fits[0].bic, 10);
}

TEST(CompareLaws, EachLawTakesTheParametersItHasByName) {
  auto options = QuickOptions();
  options.uncertainty.threads = 1;
  options.law = {dem::ContactLawKind::kWaltonBraun,
                 {{"stiffness_n_per_m", 2e7}, {"effective_modulus_pa", 5e10}}};
  const auto recording = SimulatedRecording(WaltonBraun(0.4), 6, 10e-6, 2);
  const auto comparison = CompareLaws(
      {recording}, {dem::ContactLawKind::kWaltonBraun, dem::ContactLawKind::kHertzViscoelastic},
      options);
  for (const auto& fit : comparison.fits) {
    if (fit.law.kind == dem::ContactLawKind::kWaltonBraun) {
      EXPECT_DOUBLE_EQ(fit.law.Get("stiffness_n_per_m"), 2e7);
    } else {
      EXPECT_DOUBLE_EQ(fit.law.Get("effective_modulus_pa"), 5e10);
    }
  }
}

TEST(Fit, BootstrapIsDeterministicForASeedAndIndependentOfThreads) {
  auto options = QuickOptions();
  options.uncertainty.bootstrap_samples = 8;
  const auto recording = SimulatedRecording(WaltonBraun(0.5), 6, 10e-6, 2);
  options.uncertainty.threads = 1;
  const auto one = Fit({recording}, options);
  options.uncertainty.threads = 2;
  const auto two = Fit({recording}, options);
  ASSERT_TRUE(one.parameters[0].confidence_interval && two.parameters[0].confidence_interval);
  EXPECT_EQ(one.parameters[0].confidence_interval->first,
            two.parameters[0].confidence_interval->first);
  EXPECT_EQ(one.parameters[0].confidence_interval->second,
            two.parameters[0].confidence_interval->second);
}

TEST(Fit, TooFewImpactsForFirstNIsAConfigError) {
  auto options = QuickOptions();
  options.first_n = 5;
  const auto recording = SimulatedRecording(WaltonBraun(0.5), 4, 10e-6, 2);
  EXPECT_THROW(Fit({recording}, options), ConfigError);
}

TEST(Fit, UnknownParameterOrBadRangeIsAConfigError) {
  auto options = QuickOptions();
  const auto recording = SimulatedRecording(WaltonBraun(0.5), 6, 10e-6, 2);
  options.fitted_parameters = {"youngs_modulus"};
  EXPECT_THROW(Fit({recording}, options), ConfigError);
  options.fitted_parameters = {"gamma_n"};
  options.ranges["gamma_n"] = {0.5, 0.2, false};
  EXPECT_THROW(Fit({recording}, options), ConfigError);
}

TEST(FitObjective, NamesRoundTrip) {
  for (auto objective :
       {FitObjective::kMeanEnergyLoss, FitObjective::kIntervals, FitObjective::kHeights}) {
    EXPECT_EQ(FitObjectiveFromString(ToString(objective)), objective);
  }
  EXPECT_THROW(FitObjectiveFromString("energy"), ConfigError);
}

}  // namespace
}  // namespace bouncecal::calibrate
