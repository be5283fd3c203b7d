#include "bouncecal/dem/drop.h"

#include <fmt/format.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "drop_contact.h"
#include "drop_flight.h"
#include "drop_state.h"

namespace bouncecal::dem {
namespace {

using internal::ContactEnd;
using internal::FlightResult;
using internal::FlyToPlane;
using internal::IntegrateContact;
using internal::Physics;
using internal::State;
using internal::TrajectoryRecorder;

constexpr std::array<std::pair<Integrator, std::string_view>, 4> kIntegratorNames = {{
    {Integrator::kVelocityVerlet, "verlet"},
    {Integrator::kSymplecticEuler, "euler"},
    {Integrator::kRungeKutta4, "rk4"},
    {Integrator::kExact, "exact"},
}};

// The laws give the limit omega dt < 2 of the explicit second-order schemes. RK4's stability
// region reaches 2 sqrt(2) = 2.83 on the imaginary axis (undamped oscillator) and 2.785 on the
// negative real axis; the smaller one also covers damped contacts.
constexpr double kRungeKutta4StabilityFactor = 2.785 / 2;
// Symplectic Euler is linearly stable to omega dt < 2 too, but its true energy departs from the
// invariant it conserves, H = v^2/2 + omega^2 x^2/2 - omega^2 dt x v / 2, by factors up to
// (1 + omega dt/2) / (1 - omega dt/2); once that exceeds the dissipation of an impact the ball
// gains energy (measured in drop_stability_test.cc). omega dt < 1 bounds it by 3.
constexpr double kSymplecticEulerStabilityFactor = 0.5;

double StabilityFactor(Integrator integrator) {
  switch (integrator) {
    case Integrator::kRungeKutta4:
      return kRungeKutta4StabilityFactor;
    case Integrator::kSymplecticEuler:
      return kSymplecticEulerStabilityFactor;
    default:
      return 1;
  }
}

double ThreadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void CheckRange(std::string_view name, double value, double min_value, double max_value,
                std::string_view unit, bool min_exclusive = false) {
  const bool ok = std::isfinite(value) &&
                  (min_exclusive ? value > min_value : value >= min_value) && value <= max_value;
  if (ok) return;
  throw ConfigError(fmt::format(
      "drop option {} = {} is outside its valid range {}{:g}, {:g}]{}{}; choose a finite value "
      "in that range",
      name, value, min_exclusive ? "(" : "[", min_value, max_value, unit.empty() ? "" : " ", unit));
}

void ValidateOptions(const DropOptions& options) {
  options.ball.Validate();
  CheckRange("drop_height_m", options.drop_height_m, 1e-9, 1e4, "m");
  CheckRange("gravity_mps2", options.gravity_mps2, 1e-3, 1e3, "m/s^2");
  CheckRange("drag.drag_coefficient", options.drag.drag_coefficient, 0, 10, "");
  CheckRange("drag.air_density_kg_per_m3", options.drag.air_density_kg_per_m3, 0, 100, "kg/m^3");
  if (options.time_step_s) CheckRange("time_step_s", *options.time_step_s, 0, 1, "s", true);
  CheckRange("steps_per_contact", options.steps_per_contact, 1, 1e7, "");
  CheckRange("max_impacts", options.max_impacts, 1, 1e9, "");
  CheckRange("max_time_s", options.max_time_s, 0, 1e6, "s", true);
  CheckRange("rest_flight_s", options.rest_flight_s, 0, 1, "s");
  CheckRange("rest_contact_factor", options.rest_contact_factor, 1, 1e9, "");
  CheckRange("max_steps", static_cast<double>(options.max_steps), 1, 1e12, "");
  CheckRange("trajectory_interval_s", options.trajectory_interval_s, 0, 1e3, "s");
}

// The contact time scale steps_per_contact divides.
template <typename Law>
double ReferenceContactDuration(const Law& law, double mass, double radius, double speed,
                                double stable) {
  const auto duration = law.ClosedFormContactDuration(mass, radius, speed);
  // pi / omega_max for laws without a closed form (or that never release).
  const double fallback = std::numbers::pi / 2 * stable;
  return duration && std::isfinite(*duration) ? *duration : fallback;
}

class DropRunner {
 public:
  DropRunner(const DropOptions& options, const Physics& physics, DropResult& result)
      : options_(options),
        physics_(physics),
        result_(result),
        recorder_(options.trajectory_interval_s, &result.trajectory) {}

  template <typename Law>
  void RunStepped(const Law& law, double dt) {
    switch (options_.integrator) {
      case Integrator::kVelocityVerlet:
        return Loop<Integrator::kVelocityVerlet>(law, dt);
      case Integrator::kSymplecticEuler:
        return Loop<Integrator::kSymplecticEuler>(law, dt);
      case Integrator::kRungeKutta4:
        return Loop<Integrator::kRungeKutta4>(law, dt);
      case Integrator::kExact:
        break;
    }
  }

  // Event-driven: closed-form flights and closed-form contacts.
  template <typename Law>
  void RunExact(const Law& law) {
    const double g = physics_.gravity_mps2;
    double t = 0, z = options_.drop_height_m, v = 0;
    for (;;) {
      const double speed_in = std::sqrt(v * v + 2 * g * z);
      const double t_on = t + (v + speed_in) / g;
      recorder_.Ballistic(t, z, v, g, std::min(t_on, options_.max_time_s));
      if (t_on > options_.max_time_s) return StopAtTimeLimit();
      const ExactImpact exact = law.SolveImpactExactly(physics_.mass_kg, g, speed_in);
      ++result_.steps;
      DropImpact impact{.time_s = t_on,
                        .restitution = exact.speed_out_mps / speed_in,
                        .energy_loss = 0,
                        .contact_duration_s = exact.duration_s,
                        .max_overlap_m = exact.max_overlap_m,
                        .speed_in_mps = speed_in,
                        .speed_out_mps = exact.speed_out_mps,
                        .released = exact.released};
      impact.energy_loss = 1 - impact.restitution * impact.restitution;
      if (!exact.released) {
        // The ball stays on the plane; it has settled by the time the contact would have ended.
        impact.contact_duration_s = 0;
        impact.restitution = 0;
        impact.energy_loss = 1;
        result_.end_time_s = t_on;
        recorder_.Segment(t_on, 0, -speed_in, t_on, 0, 0);
        return Trapped(law, impact);
      }
      t = t_on + exact.duration_s;
      recorder_.Segment(t_on, 0, -speed_in, t, 0, exact.speed_out_mps);
      if (Released(impact, t)) return;
      if (t > options_.max_time_s) return StopAtTimeLimit();
      z = 0;
      v = exact.speed_out_mps;
    }
  }

 private:
  template <Integrator kMethod, typename Law>
  void Loop(const Law& law, double dt) {
    State state{.t = 0, .z = options_.drop_height_m, .v = 0};
    for (;;) {
      const FlightResult flight = FlyToPlane(state, physics_, options_.max_time_s, recorder_);
      result_.steps += flight.steps;
      if (!flight.landed) return StopAtTimeLimit();
      DropImpact impact{.time_s = flight.time_s, .speed_in_mps = flight.speed_mps};
      State contact{.t = flight.time_s, .z = 0, .v = -flight.speed_mps};
      if (options_.fixed_step_grid) {
        // First grid step at or after the crossing, the grid continuing from the last step.
        const double steps_to_grid = std::ceil((flight.time_s - state.t) / dt);
        const double s = state.t + steps_to_grid * dt - flight.time_s;
        contact.t = flight.time_s + s;
        contact.z = -flight.speed_mps * s - 0.5 * physics_.gravity_mps2 * s * s;
        contact.v = -flight.speed_mps - physics_.gravity_mps2 * s;
      }
      state = contact;
      const double max_contact_s =
          options_.rest_contact_factor *
          ReferenceContactDuration(law, physics_.mass_kg, physics_.radius_m, flight.speed_mps,
                                   law.MaxStableTimeStepS(physics_.mass_kg, physics_.radius_m,
                                                          flight.speed_mps, physics_.gravity_mps2));
      const ContactEnd end = IntegrateContact<kMethod>(law, physics_, options_, dt, max_contact_s,
                                                       state, impact, result_.steps, recorder_);
      result_.end_time_s = state.t;
      switch (end) {
        case ContactEnd::kReleased:
          impact.restitution = impact.speed_out_mps / impact.speed_in_mps;
          impact.energy_loss = 1 - impact.restitution * impact.restitution;
          if (Released(impact, state.t)) return;
          break;
        case ContactEnd::kTrapped:
          impact.released = false;
          impact.contact_duration_s = state.t - impact.time_s;
          return Trapped(law, impact);
        case ContactEnd::kSustained:
          impact.released = false;
          impact.contact_duration_s = state.t - impact.time_s;
          Trapped(law, impact);
          result_.stop_detail = fmt::format(
              "at rest in contact: impact {} at {:.3g} m/s lasted {:.3g} s, more than "
              "rest_contact_factor = {:g} contact durations",
              result_.impacts.size(), impact.speed_in_mps, impact.contact_duration_s,
              options_.rest_contact_factor);
          return;
        case ContactEnd::kTimeLimit:
          impact.released = false;
          impact.contact_duration_s = state.t - impact.time_s;
          result_.impacts.push_back(impact);
          return StopAtTimeLimit();
        case ContactEnd::kStepLimit:
          impact.released = false;
          impact.contact_duration_s = state.t - impact.time_s;
          result_.impacts.push_back(impact);
          result_.stop_reason = DropStopReason::kStepLimit;
          result_.stop_detail =
              fmt::format("stopped after max_steps = {} integration steps at t = {:.6g} s",
                          options_.max_steps, state.t);
          return;
      }
    }
  }

  // Records a released impact; true when the drop ends here.
  bool Released(const DropImpact& impact, double release_time_s) {
    result_.impacts.push_back(impact);
    result_.end_time_s = release_time_s;
    const double next_flight = 2 * impact.speed_out_mps / physics_.gravity_mps2;
    if (next_flight < options_.rest_flight_s) {
      result_.stop_reason = DropStopReason::kAtRest;
      result_.stop_detail = fmt::format(
          "at rest: the flight after impact {} would last {:.3g} s, shorter than rest_flight_s = "
          "{:g} s",
          result_.impacts.size(), next_flight, options_.rest_flight_s);
      return true;
    }
    if (static_cast<int>(result_.impacts.size()) >= options_.max_impacts) {
      result_.stop_reason = DropStopReason::kMaxImpacts;
      result_.stop_detail = fmt::format("stopped after max_impacts = {} impacts at t = {:.6g} s",
                                        options_.max_impacts, release_time_s);
      return true;
    }
    return false;
  }

  template <typename Law>
  void Trapped(const Law& law, DropImpact impact) {
    impact.restitution = 0;
    impact.energy_loss = 1;
    impact.speed_out_mps = 0;
    impact.released = false;
    result_.impacts.push_back(impact);
    const auto law_restitution =
        law.ClosedFormRestitution(physics_.mass_kg, physics_.radius_m, impact.speed_in_mps);
    if (law_restitution && *law_restitution == 0) {
      result_.stop_reason = DropStopReason::kStuck;
      result_.stop_detail = fmt::format(
          "stuck: the contact law returns no energy (e = 0), so impact {} at {:.3g} m/s never "
          "ended",
          result_.impacts.size(), impact.speed_in_mps);
    } else {
      result_.stop_reason = DropStopReason::kAtRest;
      result_.stop_detail = fmt::format(
          "at rest in contact: after impact {} at {:.3g} m/s the remaining energy cannot lift "
          "the ball off the plane",
          result_.impacts.size(), impact.speed_in_mps);
    }
  }

  void StopAtTimeLimit() {
    result_.stop_reason = DropStopReason::kTimeLimit;
    result_.end_time_s = options_.max_time_s;
    result_.stop_detail =
        fmt::format("stopped at max_time_s = {:g} s after {} impacts; raise max_time_s",
                    options_.max_time_s, result_.impacts.size());
  }

  const DropOptions& options_;
  Physics physics_;
  DropResult& result_;
  TrajectoryRecorder recorder_;
};

Physics MakePhysics(const DropOptions& options) {
  const double mass = options.ball.MassKg();
  const double area = std::numbers::pi * options.ball.diameter_m * options.ball.diameter_m / 4;
  return {.mass_kg = mass,
          .radius_m = options.ball.RadiusM(),
          .gravity_mps2 = options.gravity_mps2,
          .drag_per_mass = options.drag.enabled ? 0.5 * options.drag.air_density_kg_per_m3 *
                                                      options.drag.drag_coefficient * area / mass
                                                : 0};
}

}  // namespace

std::string_view ToString(Integrator integrator) {
  for (const auto& [value, name] : kIntegratorNames) {
    if (value == integrator) return name;
  }
  return "unknown";
}

std::string IntegratorNames() {
  std::string names;
  for (const auto& [value, name] : kIntegratorNames) {
    if (!names.empty()) names += ", ";
    names += name;
  }
  return names;
}

Integrator IntegratorFromString(std::string_view name) {
  for (const auto& [value, known] : kIntegratorNames) {
    if (known == name) return value;
  }
  throw ConfigError(
      fmt::format("unknown integrator '{}'; valid integrators: {}", name, IntegratorNames()));
}

std::string_view ToString(DropStopReason reason) {
  switch (reason) {
    case DropStopReason::kMaxImpacts:
      return "max_impacts";
    case DropStopReason::kTimeLimit:
      return "time_limit";
    case DropStopReason::kAtRest:
      return "at_rest";
    case DropStopReason::kStuck:
      return "stuck";
    case DropStopReason::kStepLimit:
      return "step_limit";
  }
  return "unknown";
}

double Ball::MassKg() const {
  if (mass_kg) return *mass_kg;
  return density_kg_per_m3 * std::numbers::pi * diameter_m * diameter_m * diameter_m / 6;
}

double Ball::DensityKgPerM3() const {
  if (!mass_kg) return density_kg_per_m3;
  return *mass_kg / (std::numbers::pi * diameter_m * diameter_m * diameter_m / 6);
}

void Ball::Validate() const {
  CheckRange("ball.diameter_m", diameter_m, kMinDiameterM, kMaxDiameterM, "m");
  CheckRange("ball.density_kg_per_m3", density_kg_per_m3, kMinDensityKgPerM3, kMaxDensityKgPerM3,
             "kg/m^3");
  if (mass_kg) CheckRange("ball.mass_kg", *mass_kg, 0, kMaxMassKg, "kg", true);
}

DropStep ChooseDropStep(const DropOptions& options) {
  ValidateOptions(options);
  const ContactLaw law = MakeContactLaw(options.law);
  const Physics physics = MakePhysics(options);
  const double first_speed = std::sqrt(2 * options.gravity_mps2 * options.drop_height_m);
  return std::visit(
      [&](const auto& typed) {
        DropStep step;
        const double stable = typed.MaxStableTimeStepS(physics.mass_kg, physics.radius_m,
                                                       first_speed, physics.gravity_mps2);
        step.contact_duration_s =
            ReferenceContactDuration(typed, physics.mass_kg, physics.radius_m, first_speed, stable);
        step.stability_limit_s = stable * StabilityFactor(options.integrator);
        const double resolved = std::min(step.contact_duration_s, std::numbers::pi * stable);
        step.time_step_s =
            options.time_step_s ? *options.time_step_s : resolved / options.steps_per_contact;
        step.min_steps_per_contact = resolved / step.stability_limit_s;
        return step;
      },
      law);
}

DropResult SimulateDrop(const DropOptions& options) {
  const double cpu_start = ThreadCpuSeconds();
  const DropStep step = ChooseDropStep(options);
  const ContactLaw law = MakeContactLaw(options.law);
  const Physics physics = MakePhysics(options);
  DropResult result;
  result.stability_limit_s = step.stability_limit_s;
  DropRunner runner(options, physics, result);
  if (options.integrator == Integrator::kExact) {
    if (!SupportsExactImpacts(law)) {
      throw OptionError({"integrator"},
                        fmt::format("the exact integrator needs a piecewise-linear law ({}), not "
                                    "{}; set `integrator` to rk4 (small-step reference) or verlet",
                                    ExactImpactLawNames(), ToString(options.law.kind)));
    }
    if (options.drag.enabled) {
      throw OptionError({"integrator"},
                        "the exact integrator has no closed form with air drag; set `integrator` "
                        "to verlet or rk4 with drag");
    }
    std::visit(
        [&](const auto& typed) {
          if constexpr (HasExactImpact<std::decay_t<decltype(typed)>>) runner.RunExact(typed);
        },
        law);
  } else {
    if (step.time_step_s > step.stability_limit_s && !options.allow_unstable_step) {
      throw OptionError(
          {"steps_per_contact", "allow_unstable_step"},
          fmt::format(
              "time step {:.4g} s exceeds the stability limit {:.4g} s of {} with the {} "
              "integrator "
              "for this ball; use a step below it (steps_per_contact >= {:.3g}) or allow it "
              "explicitly (allow_unstable_step)",
              step.time_step_s, step.stability_limit_s, ToString(options.law.kind),
              ToString(options.integrator), step.min_steps_per_contact));
    }
    result.time_step_s = step.time_step_s;
    std::visit([&](const auto& typed) { runner.RunStepped(typed, step.time_step_s); }, law);
  }
  result.cpu_s = ThreadCpuSeconds() - cpu_start;
  return result;
}

}  // namespace bouncecal::dem
