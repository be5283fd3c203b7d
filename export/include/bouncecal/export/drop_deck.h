#ifndef BOUNCECAL_EXPORT_DROP_DECK_H_
#define BOUNCECAL_EXPORT_DROP_DECK_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/export/engine.h"
#include "bouncecal/export/export_material.h"
#include "bouncecal/export/law_mapping.h"

namespace bouncecal::calibrate {

// One file of an exported deck: its name inside the deck folder and its full text.
struct DeckFile {
  std::string name;
  std::string content;
};

struct DeckBall {
  double diameter_m = 0.01;
  double mass_kg = 0;  // the engine gets the density that reproduces this mass exactly
};

struct DropDeckOptions {
  Engine engine = Engine::kLammps;
  // Gap between the ball's lowest point and the wall at release, from rest.
  double drop_height_m = 0.2;
  double gravity_mps2 = 9.81;
  // Absolute time step; when empty, the largest step whose restitution error bound (below) stays
  // within max_time_step_error, and never more than contact_duration / kMinStepsPerContact.
  std::optional<double> time_step_s;
  // The spring-dashpot's damping force jumps to m gamma_n v at contact onset and is still
  // m gamma_n v_out at separation; a fixed step places both jumps to within one step, which
  // bounds the relative restitution error by about 2 |ln e| dt / t_c = gamma_n dt. Measured with
  // LAMMPS (e = 0.577): dt = t_c/70 gave -0.96 % .. +0.6 %, dt = t_c/400 gave -0.1 % .. +0.18 %
  // depending on the phase of the onset within a step; both inside the bound.
  double max_time_step_error = 0.002;
  // The run lasts until the ball has left the wall this many times (closed-form flights).
  int bounces = 8;
  // Named in the header (provenance): typically the material card's path.
  std::string material_source = "(material given in memory)";
};

inline constexpr double kMinStepsPerContact = 100;

struct Deck {
  std::vector<DeckFile> files;  // the input script first (single drop: then deck.json)
  std::string input_file_name;  // "in.drop"
  std::string run_command;      // to run inside the deck folder, e.g. "lmp -in in.drop ..."
  std::string trajectory_file_name = "trajectory.txt";
  double time_step_s = 0;
  std::int64_t steps = 0;
  double duration_s = 0;
  int output_every_steps = 1;
  double output_interval_s = 0;
  // What the engine should produce for every wall bounce: the card law's restitution, and the
  // bound on the relative deviation the time step allows (gravity during contact adds about
  // g t_c / v_impact on top, negligible for the first bounces: the header says how much).
  double expected_restitution = 0;
  double time_step_error_bound = 0;
  // Human sentences: the mapping and the expected deviation (also written into the header).
  std::vector<std::string> notes;
};

// The single-drop check scene: one ball released from rest above a wall at z = 0, integrated
// with nve/sphere under gravity, writing `time z vz` of its centre to trajectory.txt. A pure
// function of its inputs, so decks are unit-testable; the caller writes the files. Throws
// ConfigError naming the option and its valid range.
Deck MakeDropDeck(const LawMapping& mapping, const DeckBall& ball, const DropDeckOptions& options);

// The whole export of a card's single-drop check: MapContactLaw at the drop's first impact speed
// sqrt(2 g h), then MakeDropDeck. options.material_source is taken from material.source.
Deck ExportDropDeck(const ExportMaterial& material, const DropDeckOptions& options);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_DROP_DECK_H_
