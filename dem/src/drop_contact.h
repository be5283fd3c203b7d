#ifndef BOUNCECAL_DEM_SRC_DROP_CONTACT_H_
#define BOUNCECAL_DEM_SRC_DROP_CONTACT_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "bouncecal/dem/drop.h"
#include "drop_state.h"

namespace bouncecal::dem::internal {

// Which branch of a hysteretic law a (sub)step may use: the velocity handed to the force is
// clamped to that sign, so the sign switch of sgn(d xi/dt) happens exactly at a located turning
// point and not somewhere inside a step.
enum class Branch { kFree, kLoading, kUnloading };

inline double BranchVelocity(double v, Branch branch) {
  constexpr double kTiny = std::numeric_limits<double>::min();
  switch (branch) {
    case Branch::kFree:
      return v;
    case Branch::kLoading:  // moving down (overlap growing)
      return std::min(v, -kTiny);
    case Branch::kUnloading:
      return std::max(v, kTiny);
  }
  return v;
}

template <typename Law>
double Acceleration(const Law& law, const Physics& physics, double z, double v,
                    NormalHistory& history) {
  double a = -physics.gravity_mps2 - physics.drag_per_mass * v * std::abs(v);
  // Touching and approaching counts as contact: laws whose force jumps at touchdown (dashpot)
  // then act from the first instant of the contact.
  if (z < 0 || (z == 0 && v < 0)) {
    const NormalContact contact{.overlap_m = -z,
                                .overlap_rate_mps = -v,
                                .effective_mass_kg = physics.mass_kg,
                                .effective_radius_m = physics.radius_m};
    a += law.NormalForce(contact, history) / physics.mass_kg;
  }
  return a;
}

// One integrator on one contact: the state, the law's history and (Verlet) the cached
// acceleration.
template <Integrator kMethod, typename Law>
class ContactStepper {
 public:
  ContactStepper(const Law& law, const Physics& physics) : law_(&law), physics_(&physics) {}

  // grid_entry: the contact starts at a grid step that already has overlap (classic stepping).
  // A Verlet code reaching that step has applied half a kick of the contact force there
  // (v = v_half + dt/2 a with the new force), which the ballistic state lacks: add it.
  void Start(State& state, double dt, bool grid_entry) {
    history_ = {};
    if constexpr (kMethod == Integrator::kVelocityVerlet) {
      acceleration_ = Acceleration(*law_, *physics_, state.z, state.v, history_);
      if (grid_entry) {
        NormalHistory none;
        state.v += 0.5 * dt * (acceleration_ - Acceleration(*law_, *physics_, 1.0, state.v, none));
      }
    }
  }

  void Step(State& state, double dt, Branch branch) {
    if constexpr (kMethod == Integrator::kVelocityVerlet) {
      // Kick-drift-kick; the force sees the half-step velocity (LAMMPS' initial/final
      // integrate order), so there is one force evaluation per step.
      const double v_half = state.v + 0.5 * dt * acceleration_;
      state.z += dt * v_half;
      acceleration_ =
          Acceleration(*law_, *physics_, state.z, BranchVelocity(v_half, branch), history_);
      state.v = v_half + 0.5 * dt * acceleration_;
    } else if constexpr (kMethod == Integrator::kSymplecticEuler) {
      state.v +=
          dt * Acceleration(*law_, *physics_, state.z, BranchVelocity(state.v, branch), history_);
      state.z += dt * state.v;
    } else {
      // Stages see a copy of the history; the step's end state commits it once.
      const auto f = [&](double z, double v) {
        NormalHistory trial = history_;
        return Acceleration(*law_, *physics_, z, BranchVelocity(v, branch), trial);
      };
      const double k1z = state.v, k1v = f(state.z, state.v);
      const double k2z = state.v + 0.5 * dt * k1v, k2v = f(state.z + 0.5 * dt * k1z, k2z);
      const double k3z = state.v + 0.5 * dt * k2v, k3v = f(state.z + 0.5 * dt * k2z, k3z);
      const double k4z = state.v + dt * k3v, k4v = f(state.z + dt * k3z, k4z);
      state.z += dt / 6 * (k1z + 2 * k2z + 2 * k3z + k4z);
      state.v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      if constexpr (Law::kNeedsHistory) {
        Acceleration(*law_, *physics_, state.z, state.v, history_);
      }
    }
    state.t += dt;
  }

  // At a turning point (v = 0): the accelerations just after it on the unloading (upward) and
  // the loading (downward) branch.
  std::pair<double, double> TurningAccelerations(double z) const {
    NormalHistory up = history_, down = history_;
    return {Acceleration(*law_, *physics_, z, BranchVelocity(0, Branch::kUnloading), up),
            Acceleration(*law_, *physics_, z, BranchVelocity(0, Branch::kLoading), down)};
  }

  // Continue from a turning point in the given direction (Verlet needs the matching force).
  void Turn(const State& state, Branch branch) {
    if constexpr (kMethod == Integrator::kVelocityVerlet) {
      acceleration_ = Acceleration(*law_, *physics_, state.z, BranchVelocity(0, branch), history_);
    }
  }

  double ReturnableEnergy(const State& state) const {
    const NormalContact contact{.overlap_m = -state.z,
                                .overlap_rate_mps = -state.v,
                                .effective_mass_kg = physics_->mass_kg,
                                .effective_radius_m = physics_->radius_m};
    return law_->ReturnableEnergyJ(contact, history_);
  }

 private:
  const Law* law_;  // pointers keep the stepper copyable (a step is redone from a copy)
  const Physics* physics_;
  NormalHistory history_;
  double acceleration_ = 0;
};

// Finds the sub-step s in (0, dt] after which value(state) crosses 0, given its values at the
// start and after the full step (of opposite signs), by regula falsi with the Illinois
// modification on the sub-step length: each trial re-integrates the sub-step from the saved
// stepper, so the event is located on the integrator's own trajectory, whatever the step size.
// Leaves the state and stepper at the event and returns s.
template <typename Stepper, typename Value>
double LocateEvent(const Stepper& saved, const State& start, double dt, Branch branch,
                   double value_start, double value_end, Value value, State& state,
                   Stepper& stepper) {
  double lo = 0, hi = dt, f_lo = value_start, f_hi = value_end;
  const double tolerance = 1e-12 * std::max(std::abs(value_start), std::abs(value_end));
  double s = dt * value_start / (value_start - value_end);
  int side = 0;
  for (int iteration = 0; iteration < 30; ++iteration) {
    stepper = saved;
    state = start;
    stepper.Step(state, s, branch);
    const double f = value(state);
    if (std::abs(f) <= tolerance || hi - lo <= 1e-12 * dt) break;
    if ((f < 0) == (f_lo < 0)) {
      lo = s;
      f_lo = f;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    } else {
      hi = s;
      f_hi = f;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
    s = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
  }
  return s;
}

enum class ContactEnd { kReleased, kTrapped, kSustained, kTimeLimit, kStepLimit };

// One contact integrated with a fixed step from `state` (overlap >= 0, approaching) until the
// ball is released, can never be released, stays longer than max_contact_s (sustained contact:
// resting on the plane while a weakly damped ring-down decays), or the time or step budget
// ends.
//
// With options.locate_contact_events, a step in which the velocity changes sign is redone as
// two sub-steps split at the turning point (located by LocateEvent), with the law's loading branch
// before it and the unloading branch after, and the step in which the ball leaves the plane is
// redone up to the crossing. There the contact behaves like Coulomb friction in
// velocity space (Filippov): if neither branch can move the ball (upward acceleration <= 0 on
// the unloading branch, >= 0 on the loading one) it stays put, i.e. it is trapped. Without it,
// the branch switches at a step boundary as in a classic DEM code, which overshoots the turning
// point by up to a step (e > 0 even for gamma_n = 1).
template <Integrator kMethod, typename Law>
ContactEnd IntegrateContact(const Law& law, const Physics& physics, const DropOptions& options,
                            double dt, double max_contact_s, State& state, DropImpact& impact,
                            std::int64_t& steps, TrajectoryRecorder& recorder) {
  ContactStepper<kMethod, Law> stepper(law, physics);
  stepper.Start(state, dt, options.fixed_step_grid && state.z < 0);
  const double m = physics.mass_kg;
  const double g = physics.gravity_mps2;
  for (;;) {
    if (steps >= options.max_steps) return ContactEnd::kStepLimit;
    const State previous = state;
    const ContactStepper<kMethod, Law> saved = stepper;
    stepper.Step(state, dt, Branch::kFree);
    ++steps;
    if (options.locate_contact_events && previous.v * state.v < 0 && state.z < 0) {
      const Branch before = previous.v < 0 ? Branch::kLoading : Branch::kUnloading;
      const double v_end = state.v;
      const double sub_step = LocateEvent(
          saved, previous, dt, before, previous.v, v_end, [](const State& at) { return at.v; },
          state, stepper);
      state.v = 0;
      const auto [up, down] = stepper.TurningAccelerations(state.z);
      recorder.Segment(previous.t, previous.z, previous.v, state.t, state.z, state.v);
      if (up <= 0 && down >= 0) {
        impact.max_overlap_m = std::max(impact.max_overlap_m, -state.z);
        return ContactEnd::kTrapped;
      }
      impact.max_overlap_m = std::max(impact.max_overlap_m, -state.z);  // exact at v = 0
      const Branch after = up > 0 ? Branch::kUnloading : Branch::kLoading;
      stepper.Turn(state, after);
      const State mid = state;
      stepper.Step(state, dt - sub_step, after);
      ++steps;
      state.t = previous.t + dt;
      recorder.Segment(mid.t, mid.z, mid.v, state.t, state.z, state.v);
    } else if (options.locate_contact_events && state.z >= 0 && previous.z < 0) {
      // Release inside the step: redo it up to the crossing, so that no part of the step feels
      // the force jump there (the dashpot's pull ends at overlap 0).
      LocateEvent(
          saved, previous, dt, Branch::kFree, previous.z, state.z,
          [](const State& at) { return at.z; }, state, stepper);
      recorder.Segment(previous.t, previous.z, previous.v, state.t, state.z, state.v);
      state.z = std::max(state.z, 0.0);  // what remains is below the location tolerance
    } else {
      recorder.Segment(previous.t, previous.z, previous.v, state.t, state.z, state.v);
    }
    impact.max_overlap_m = std::max(impact.max_overlap_m, -state.z);
    if (state.z >= 0) {
      // Force-free since the crossing: go back along the parabola to overlap 0 (drag over a
      // fraction of a step is negligible).
      const double speed = std::sqrt(state.v * state.v + 2 * g * state.z);
      const double back = (speed - state.v) / g;
      impact.speed_out_mps = speed;
      impact.contact_duration_s = state.t - back - impact.time_s;
      return ContactEnd::kReleased;
    }
    // Can the ball still leave? Kinetic energy plus the most the law can give back must exceed
    // the work m g xi to lift it out; dissipation and drag only lower the left side.
    if (0.5 * m * state.v * state.v + stepper.ReturnableEnergy(state) < m * g * (-state.z)) {
      return ContactEnd::kTrapped;
    }
    if (state.t - impact.time_s > max_contact_s) return ContactEnd::kSustained;
    if (state.t >= options.max_time_s) return ContactEnd::kTimeLimit;
  }
}

}  // namespace bouncecal::dem::internal

#endif  // BOUNCECAL_DEM_SRC_DROP_CONTACT_H_
