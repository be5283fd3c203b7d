#ifndef BOUNCECAL_DEM_DROP_H_
#define BOUNCECAL_DEM_DROP_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::dem {

// How the contact phase of a drop is integrated. Flights without drag are always solved in
// closed form (a parabola), so the step only has to resolve contacts.
enum class Integrator {
  kVelocityVerlet,   // "verlet": second order, symplectic; force evaluated with the half-step
                     // velocity, as LAMMPS/LIGGGHTS do (default)
  kSymplecticEuler,  // "euler": first order; v += a dt, x += v dt, what classic DEM codes use
  kRungeKutta4,      // "rk4": fourth order, the small-step reference for nonlinear laws
  kExact,            // "exact": event-driven closed form, piecewise-linear laws only, no drag
};
std::string_view ToString(Integrator integrator);
// Throws ConfigError naming the value and the valid names.
Integrator IntegratorFromString(std::string_view name);
std::string IntegratorNames();  // "verlet, euler, rk4, exact"

enum class DropStopReason {
  kMaxImpacts,  // options.max_impacts impacts were simulated
  kTimeLimit,   // options.max_time_s was reached
  kAtRest,      // the bounces became shorter than rest_flight_s, or the ball stayed in contact
                // (its remaining energy cannot lift it off the plane any more, or the contact
                // lasted rest_contact_factor contact durations)
  kStuck,       // the law returns no energy at all (e = 0, e.g. gamma_n = 1): the first contact
                // never ends
  kStepLimit,   // options.max_steps integration steps were taken (guarantees finite work)
};
std::string_view ToString(DropStopReason reason);

// A ball is given by its size and either its density (solid) or its mass (hollow balls, whose
// shell density says nothing about their mass). Whoever reports the ball reads MassKg() and
// DensityKgPerM3(), never the density field alone: with a mass set, that field is a leftover
// default (a tennis-ball card once recorded steel's 7800 kg/m^3 beside its 57.7 g).
struct Ball {
  // The valid ranges, named once for Validate and for the front ends' ball rules
  // (calibrate::ResolveBall).
  static constexpr double kMinDiameterM = 1e-6;
  static constexpr double kMaxDiameterM = 10;
  static constexpr double kMinDensityKgPerM3 = 1;
  static constexpr double kMaxDensityKgPerM3 = 1e5;
  static constexpr double kMaxMassKg = 1e6;  // and above 0

  double diameter_m = 0.01;         // [kMinDiameterM, kMaxDiameterM]
  double density_kg_per_m3 = 7800;  // [kMin.., kMaxDensityKgPerM3]; ignored when mass_kg is set
  std::optional<double> mass_kg;    // overrides density when set, (0, kMaxMassKg]
  double MassKg() const;
  // The mean density of the ball: mass_kg / (pi d^3 / 6) when the mass is set, else the density.
  double DensityKgPerM3() const;
  double RadiusM() const { return diameter_m / 2; }
  void Validate() const;  // ConfigError naming the field and its range
};

// Quadratic air drag F = -(1/2) rho_air C_d (pi d^2 / 4) v |v|. Light balls (ping-pong) need it:
// their apparent restitution otherwise depends on the drop height. Off by default, and a drop
// without drag pays nothing for it (flights stay closed-form).
struct AirDrag {
  bool enabled = false;
  double drag_coefficient = 0.47;        // C_d of a smooth sphere at Re ~ 1e4-1e5, [0, 10]
  double air_density_kg_per_m3 = 1.204;  // 20 C, sea level, [0, 100]
};

struct DropOptions {
  ContactLawConfig law;
  Ball ball;
  // Gap between the ball's lowest point and the plane at release (from rest), [1e-9, 1e4].
  double drop_height_m = 0.2;
  double gravity_mps2 = 9.81;  // [1e-3, 1e3]
  AirDrag drag;
  Integrator integrator = Integrator::kVelocityVerlet;
  // Absolute step (0, 1] s; when unset, the step is
  //   min(t_c, 2 pi / omega_max) / steps_per_contact,
  // t_c the law's contact duration at the first impact speed (gravity-free closed form; pi /
  // omega_max for laws without one) and omega_max = sqrt(stiffest tangent stiffness / m), so
  // both the whole contact and the stiffest branch's oscillation get steps_per_contact steps.
  std::optional<double> time_step_s;
  // [1, 1e7]. 50: velocity Verlet keeps eta_1 within 4e-4 of the exact path on walton-braun
  // (2.4e-4 plastic, 4e-6 hertz, 3.5e-3 dashpot); its cost per drop is in docs/drop_accuracy.md.
  double steps_per_contact = 50;
  // A step beyond the integrator's stability limit for this law is refused unless set.
  bool allow_unstable_step = false;
  // false: each contact starts exactly at overlap 0, found from the closed-form flight (no
  // onset-phase error). true: one fixed step grid from the release, and the contact force
  // switches on at the first grid step with overlap, as in a classic DEM code (the paper's
  // set-up); the onset time is still reported interpolated to overlap 0.
  bool fixed_step_grid = false;
  // true: a step in which the velocity changes sign is split at the turning point, where
  // hysteretic laws switch branch (a ball that neither branch can move stays put: exact
  // sticking for gamma_n = 1), and the step in which the ball leaves the plane ends at the
  // crossing, where the force may jump (dashpot). false: forces switch at step boundaries, as
  // in a classic DEM code (the paper's set-up); with fixed_step_grid = true and this false the
  // run is exactly a classic fixed-step DEM drop.
  bool locate_contact_events = true;
  int max_impacts = 1000;  // [1, 1e9]
  double max_time_s = 60;  // (0, 1e6]
  // The ball is at rest when the flight after an impact (predicted from the take-off speed,
  // 2 v / g) would be shorter than this, [0, 1]. 1e-5 s is half a sample at 48 kHz: no
  // recording resolves such bounces. Contacts that can never release (remaining kinetic plus
  // returnable elastic energy below the work to lift the ball out) also end the drop.
  double rest_flight_s = 1e-5;
  // A contact lasting more than this many contact durations (the law's, at that impact's speed)
  // is sustained: the ball rests on the plane while a weakly damped ring-down decays, [1, 1e9].
  // Bounds the work of a contact to this many times steps_per_contact steps.
  double rest_contact_factor = 100;
  std::int64_t max_steps = 200'000'000;  // [1, 1e12]
  double trajectory_interval_s = 0;      // 0: no trajectory recorded, else (0, 1e3]
};

struct DropImpact {
  double time_s = 0;       // contact onset (overlap 0), interpolated within the step
  double restitution = 0;  // speed_out / speed_in, at overlap 0
  double energy_loss = 0;  // 1 - e^2
  // Onset to release (overlap back to 0). For a final contact that never releases: onset to
  // the end of the simulation.
  double contact_duration_s = 0;
  double max_overlap_m = 0;
  double speed_in_mps = 0;
  double speed_out_mps = 0;  // 0 when not released
  bool released = true;      // false for a final contact the ball never left
};

struct TrajectoryPoint {
  double time_s = 0;
  double height_m = 0;      // of the lowest point of the ball; negative = overlap
  double velocity_mps = 0;  // upward positive
};

struct DropResult {
  std::vector<DropImpact> impacts;
  DropStopReason stop_reason = DropStopReason::kAtRest;
  std::string stop_detail;       // one human sentence
  std::int64_t steps = 0;        // integration steps (contact and drag flights); exact: segments
  double time_step_s = 0;        // the contact step used (0 for the exact path)
  double stability_limit_s = 0;  // the integrator's stability limit for this law and ball
  double end_time_s = 0;
  double cpu_s = 0;  // thread CPU time of the call
  std::vector<TrajectoryPoint> trajectory;
};

// Throws ConfigError on nonsense input (each field named with its valid range), on a step
// beyond the stability limit (unless allowed), and for kExact with a nonlinear law or drag.
DropResult SimulateDrop(const DropOptions& options);

// The contact step SimulateDrop would use, and the integrator's stability limit (for help
// texts and benchmarks). Throws like SimulateDrop for invalid options.
struct DropStep {
  double time_step_s = 0;
  double stability_limit_s = 0;
  double contact_duration_s = 0;     // the reference contact duration at the first impact
  double min_steps_per_contact = 0;  // fewer steps per contact exceed the stability limit
};
DropStep ChooseDropStep(const DropOptions& options);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_DROP_H_
