#include "bouncecal/export/drop_deck.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouncecal/error.h"
#include "bouncecal/export/drop_deck_check.h"
#include "bouncecal/version.h"
#include "deck_preamble.h"
#include "deck_text.h"

namespace bouncecal::calibrate {
namespace {

using deck_text::CommentBlock;
using deck_text::LammpsPreamble;
using deck_text::LiggghtsPreamble;
using deck_text::Number;
using deck_text::RequirePositive;

void Validate(const LawMapping& mapping, const DeckBall& ball, const DropDeckOptions& options) {
  RequirePositive(options.drop_height_m, "drop height", "metres");
  RequirePositive(options.gravity_mps2, "gravity", "m/s^2");
  RequirePositive(ball.diameter_m, "ball diameter", "metres");
  RequirePositive(ball.mass_kg, "ball mass", "kilograms");
  if (options.time_step_s) RequirePositive(*options.time_step_s, "time step", "seconds");
  if (!(options.max_time_step_error > 0 && options.max_time_step_error <= 0.5)) {
    throw ConfigError(fmt::format("maximum time-step restitution error must be in (0, 0.5], got {}",
                                  options.max_time_step_error));
  }
  if (options.bounces < 1 || options.bounces > 1000) {
    throw ConfigError(
        fmt::format("number of bounces must be in [1, 1000], got {}", options.bounces));
  }
  for (const SpringDashpot* law : {&mapping.wall, &mapping.pair}) {
    RequirePositive(law->stiffness_n_per_m, "mapped stiffness", "N/m");
    RequirePositive(law->effective_mass_kg, "mapped effective mass", "kilograms");
    if (!std::isfinite(law->damping_rate_per_s) || law->damping_rate_per_s < 0) {
      throw ConfigError(fmt::format("mapped damping rate gamma_n must be >= 0 1/s, got {}",
                                    law->damping_rate_per_s));
    }
    if (!(Restitution(*law) > 0)) {
      throw ConfigError(
          "the mapped spring-dashpot is overdamped (the ball would never rebound); the law "
          "cannot be checked with a drop");
    }
  }
}

// Rounded down to three significant digits so that the step printed in the deck is the step
// used for every figure derived from it.
double RoundDownToThreeDigits(double value) {
  const double scale = std::pow(10.0, std::floor(std::log10(value)) - 2);
  return std::floor(value / scale) * scale;
}

std::string TrajectoryTitle(double diameter_m) {
  return fmt::format("# time_s z_m vz_mps (ball centre; wall at z = 0; radius_m = {})",
                     Number(0.5 * diameter_m));
}

struct Timeline {
  double release_z_m;  // ball centre at release
  double duration_s;
  double last_flight_s;
};

// Closed-form flights of the mapped law (gravity during contact neglected), to size the run.
Timeline PlanTimeline(double restitution, double contact_s, double radius_m,
                      const DropDeckOptions& options) {
  const double g = options.gravity_mps2;
  const double v1 = std::sqrt(2 * g * options.drop_height_m);
  double duration = v1 / g;  // the fall to the first touch
  double speed = v1;
  for (int k = 1; k <= options.bounces; ++k) {
    speed *= restitution;
    duration += contact_s + 2 * speed / g;
  }
  const double last_flight = 2 * speed / g;
  // Stop half-way through the flight after the last counted bounce: the rebound is in the data
  // and the ball is in free flight, away from the next contact.
  duration -= 0.5 * last_flight;
  return {radius_m + options.drop_height_m, duration, last_flight};
}

// Everything the engine scripts need, computed once.
struct ScriptValues {
  const LawMapping& mapping;
  double diameter_m;
  double mass_kg;
  double density_kg_per_m3;
  double gravity_mps2;
  double release_z_m;
  const Deck& deck;
};

std::string LammpsScript(const ScriptValues& v, const std::vector<std::string>& header) {
  const double d = v.diameter_m;
  std::string s = CommentBlock(header);
  s += fmt::format(
      R"(
{preamble}
# A box just large enough for the vertical flight; the wall is the plane z = 0.
region          box block {lo} {hi} {lo} {hi} {zlo} {zhi} units box
create_box      1 box
create_atoms    1 single 0 0 {z0} units box
# The density reproduces the card's mass of {mass} kg exactly.
set             atom 1 diameter {d} density {rho}
velocity        all set 0 0 0 units box

# Pair contacts (two equal spheres, m_eff = m/2): Kn Kt gamma_n gamma_t xmu dampflag.
# No friction: the drop is head-on, so tangential terms would never act.
pair_style      gran/hooke/history {kp} 0 {gp} 0 0 0
pair_coeff      * *
neighbor        {skin} bin

fix             integrate all nve/sphere
fix             gravity all gravity {g} vector 0 0 -1
# Sphere-on-wall contacts (m_eff = m), the contact the drop calibration measured.
fix             floor all wall/gran hooke/history {kw} 0 {gw} 0 0 0 zplane 0.0 NULL

timestep        {dt}
variable        t equal time
variable        z equal z[1]
variable        vz equal vz[1]
fix             trajectory all print {every} "${{t}} ${{z}} ${{vz}}" file {traj} screen no title "{title}"
thermo          {thermo}
run             {steps}
)",
      fmt::arg("preamble", LammpsPreamble(3, /*atom_map=*/true)), fmt::arg("lo", Number(-d)),
      fmt::arg("hi", Number(d)), fmt::arg("zlo", Number(-0.5 * d)),
      fmt::arg("zhi", Number(v.release_z_m + d)), fmt::arg("z0", Number(v.release_z_m)),
      fmt::arg("mass", Number(v.mass_kg)), fmt::arg("d", Number(d)),
      fmt::arg("rho", Number(v.density_kg_per_m3)),
      fmt::arg("kp", Number(v.mapping.pair.stiffness_n_per_m)),
      fmt::arg("gp", Number(v.mapping.pair.damping_rate_per_s)), fmt::arg("skin", Number(0.1 * d)),
      fmt::arg("g", Number(v.gravity_mps2)),
      fmt::arg("kw", Number(v.mapping.wall.stiffness_n_per_m)),
      fmt::arg("gw", Number(v.mapping.wall.damping_rate_per_s)),
      fmt::arg("dt", Number(v.deck.time_step_s)), fmt::arg("every", v.deck.output_every_steps),
      fmt::arg("traj", v.deck.trajectory_file_name), fmt::arg("title", TrajectoryTitle(d)),
      fmt::arg("thermo", std::max<std::int64_t>(1, v.deck.steps / 10)),
      fmt::arg("steps", v.deck.steps));
  return s;
}

// LIGGGHTS takes contact coefficients per pair of atom types; the wall is given its own type
// (2) so that ball-ball (1-1) and ball-wall (1-2) contacts carry their own damping rate.
std::string LiggghtsScript(const ScriptValues& v, const std::vector<std::string>& header) {
  const double d = v.diameter_m;
  const auto& wall = v.mapping.wall;
  const auto& pair = v.mapping.pair;
  auto per_type_pair = [](double ball_ball, double ball_wall) {
    // Matrix order 11 12 21 22; the wall-wall entry is never used.
    return fmt::format("{0} {1} {1} {1}", Number(ball_ball), Number(ball_wall));
  };
  std::string s = CommentBlock(header);
  s += fmt::format(
      R"(
{preamble}
# A box just large enough for the vertical flight; the wall is the plane z = 0.
region          box block {lo} {hi} {lo} {hi} {zlo} {zhi} units box
create_box      2 box
neighbor        {skin} bin
neigh_modify    delay 0

# model hooke/stiffness with absolute_damping off: F = kn xi + m_eff gamman dxi/dt.
# Type 1 is the ball, type 2 the wall (1-1: m_eff = m/2, 1-2: m_eff = m).
fix             m1 all property/global kn peratomtypepair 2 {kn}
fix             m2 all property/global kt peratomtypepair 2 0 0 0 0
fix             m3 all property/global gamman peratomtypepair 2 {gn}
fix             m4 all property/global gammat peratomtypepair 2 0 0 0 0
fix             m5 all property/global coefficientFriction peratomtypepair 2 0 0 0 0

pair_style      gran model hooke/stiffness tangential no_history
pair_coeff      * *
timestep        {dt}

fix             gravity all gravity {g} vector 0.0 0.0 -1.0
fix             floor all wall/gran model hooke/stiffness tangential no_history primitive type 2 zplane 0.0

create_atoms    1 single 0 0 {z0} units box
# The density reproduces the card's mass of {mass} kg exactly.
set             atom 1 diameter {d} density {rho}
velocity        all set 0 0 0 units box
fix             integrate all nve/sphere

variable        t equal time
variable        z equal z[1]
variable        vz equal vz[1]
fix             trajectory all print {every} "${{t}} ${{z}} ${{vz}}" file {traj} screen no title "{title}"
thermo          {thermo}
run             {steps}
)",
      fmt::arg("preamble", LiggghtsPreamble()), fmt::arg("lo", Number(-d)),
      fmt::arg("hi", Number(d)), fmt::arg("zlo", Number(-0.5 * d)),
      fmt::arg("zhi", Number(v.release_z_m + d)), fmt::arg("skin", Number(0.1 * d)),
      fmt::arg("kn", per_type_pair(pair.stiffness_n_per_m, wall.stiffness_n_per_m)),
      fmt::arg("gn", per_type_pair(pair.damping_rate_per_s, wall.damping_rate_per_s)),
      fmt::arg("dt", Number(v.deck.time_step_s)), fmt::arg("g", Number(v.gravity_mps2)),
      fmt::arg("z0", Number(v.release_z_m)), fmt::arg("mass", Number(v.mass_kg)),
      fmt::arg("d", Number(d)), fmt::arg("rho", Number(v.density_kg_per_m3)),
      fmt::arg("every", v.deck.output_every_steps), fmt::arg("traj", v.deck.trajectory_file_name),
      fmt::arg("title", TrajectoryTitle(d)),
      fmt::arg("thermo", std::max<std::int64_t>(1, v.deck.steps / 10)),
      fmt::arg("steps", v.deck.steps));
  return s;
}

}  // namespace

Deck MakeDropDeck(const LawMapping& mapping, const DeckBall& ball, const DropDeckOptions& options) {
  Validate(mapping, ball, options);
  Deck deck;
  const double restitution = Restitution(mapping.wall);
  const double contact_s = ContactDurationS(mapping.wall);
  const double log_e = std::max(0.0, -std::log(restitution));  // 0, not -0, for e = 1

  if (options.time_step_s) {
    deck.time_step_s = *options.time_step_s;
  } else {
    const double by_error = log_e > 0 ? options.max_time_step_error * contact_s / (2 * log_e)
                                      : contact_s / kMinStepsPerContact;
    deck.time_step_s = RoundDownToThreeDigits(std::min(by_error, contact_s / kMinStepsPerContact));
  }
  deck.time_step_error_bound = 2 * log_e * deck.time_step_s / contact_s;
  // Velocity Verlet (both engines) is stable for omega dt < 2; a step near it is useless here.
  const double omega = std::sqrt(mapping.wall.stiffness_n_per_m / mapping.wall.effective_mass_kg);
  if (omega * deck.time_step_s >= 2) {
    throw ConfigError(fmt::format(
        "time step {} s is unstable for the mapped wall contact (omega dt = {:.3g} >= 2, t_c = "
        "{:.3g} s); give a step below {:.3g} s, or none to get one from `max_step_error`",
        deck.time_step_s, omega * deck.time_step_s, contact_s, contact_s / kMinStepsPerContact));
  }

  const double radius = 0.5 * ball.diameter_m;
  const Timeline timeline = PlanTimeline(restitution, contact_s, radius, options);
  deck.duration_s = timeline.duration_s;
  deck.steps = static_cast<std::int64_t>(std::ceil(timeline.duration_s / deck.time_step_s));
  // About two lines per contact duration, and at least eight per flight of the last bounce, so
  // every flight has free-flight samples on both sides of each contact.
  const double by_contact = std::floor(0.5 * contact_s / deck.time_step_s);
  const double by_flight = std::floor(timeline.last_flight_s / (8 * deck.time_step_s));
  deck.output_every_steps = static_cast<int>(std::max(1.0, std::min(by_contact, by_flight)));
  deck.output_interval_s = deck.output_every_steps * deck.time_step_s;
  deck.expected_restitution = restitution;

  const double g = options.gravity_mps2;
  const double first_speed = std::sqrt(2 * g * options.drop_height_m);
  double last_speed = first_speed;
  for (int k = 1; k < options.bounces; ++k) last_speed *= restitution;
  deck.notes = mapping.notes;
  deck.notes.push_back(fmt::format(
      "Time step {} s = t_c / {:.0f} (t_c = {:.4g} s for a wall contact): the damping force "
      "jumps at contact onset and separation, which a fixed step places to within one step, so "
      "the restitution the engine produces may deviate by up to 2|ln e| dt / t_c = {:.2f} %.",
      Number(deck.time_step_s), contact_s / deck.time_step_s, contact_s,
      100 * deck.time_step_error_bound));
  deck.notes.push_back(deck_text::AttractiveTailNote(options.engine == Engine::kLammps));
  deck.notes.push_back(fmt::format(
      "Gravity also acts during each contact, which no closed form includes: about g t_c / v = "
      "{:.3f} % at the first impact ({:.3g} m/s), {:.2f} % at bounce {} ({:.3g} m/s).",
      100 * g * contact_s / first_speed, first_speed, 100 * g * contact_s / last_speed,
      options.bounces, last_speed));

  deck.input_file_name = "in.drop";
  const std::string_view executable = EngineExecutable(options.engine);
  deck.run_command = fmt::format("{} -in {} -log log.{}", executable, deck.input_file_name,
                                 ToString(options.engine));

  const double volume = std::numbers::pi * std::pow(ball.diameter_m, 3) / 6;
  const ScriptValues values{mapping,
                            ball.diameter_m,
                            ball.mass_kg,
                            ball.mass_kg / volume,
                            options.gravity_mps2,
                            radius + options.drop_height_m,
                            deck};
  std::vector<std::string> header = {
      fmt::format("bouncecal single-drop check deck for {} ({})", ToString(options.engine),
                  options.engine == Engine::kLammps ? "LAMMPS 29Sep2021 or later, GRANULAR package"
                                                    : "LIGGGHTS-PUBLIC 3.x"),
      fmt::format("Written by bouncecal {} from material card: {}", Version(),
                  options.material_source),
      fmt::format("Card's contact law: {}", mapping.source_description),
      fmt::format("Ball: diameter {} m, mass {} kg, released from rest with its lowest point {} m "
                  "above the wall; g = {} m/s^2; {} bounces, {} s, {} steps.",
                  Number(ball.diameter_m), Number(ball.mass_kg), Number(options.drop_height_m),
                  Number(g), options.bounces, fmt::format("{:.4g}", deck.duration_s), deck.steps),
      ""};
  for (const auto& note : deck.notes) header.push_back(note);
  header.push_back("");
  header.push_back(fmt::format(
      "Expected restitution of every wall bounce: {:.6f} (card's law, closed form), within "
      "+-{:.2f} % from the time step.",
      restitution, 100 * deck.time_step_error_bound));
  header.push_back(fmt::format(
      "Output: {} with one line 'time_s z_m vz_mps' of the ball's centre every {} steps ({} s).",
      deck.trajectory_file_name, deck.output_every_steps, Number(deck.output_interval_s)));
  header.push_back(fmt::format("Run in this folder: {}", deck.run_command));
  header.push_back(
      "Check: 'bouncecal export-check <this folder>' after the run compares every bounce with "
      "deck.json; or by hand, v = sqrt(vz^2 + 2 g (z - r)) before and after each contact.");

  const std::string script = options.engine == Engine::kLammps ? LammpsScript(values, header)
                                                               : LiggghtsScript(values, header);
  deck.files.push_back({deck.input_file_name, script});

  DropDeckRecord record;
  record.engine = std::string(ToString(options.engine));
  record.tool_version = std::string(Version());
  record.material_source = options.material_source;
  record.trajectory_file_name = deck.trajectory_file_name;
  record.run_command = deck.run_command;
  record.ball_radius_m = radius;
  record.wall_z_m = 0;
  record.gravity_mps2 = options.gravity_mps2;
  record.time_step_s = deck.time_step_s;
  record.expected_restitution = restitution;
  record.expected_contact_duration_s = contact_s;
  record.time_step_error_bound = deck.time_step_error_bound;
  deck.files.push_back({std::string(kDropDeckRecordFileName), ToJson(record).dump(2) + "\n"});
  return deck;
}

Deck ExportDropDeck(const ExportMaterial& material, const DropDeckOptions& options) {
  RequirePositive(options.drop_height_m, "drop height", "metres");
  RequirePositive(options.gravity_mps2, "gravity", "m/s^2");
  const double impact_speed = std::sqrt(2 * options.gravity_mps2 * options.drop_height_m);
  const LawMapping mapping = MapContactLaw(material.law, material.mass_kg,
                                           0.5 * material.diameter_m, impact_speed, options.engine);
  DropDeckOptions with_source = options;
  with_source.material_source = material.source;
  return MakeDropDeck(mapping, {material.diameter_m, material.mass_kg}, with_source);
}

}  // namespace bouncecal::calibrate
