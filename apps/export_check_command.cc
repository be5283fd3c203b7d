#include <fmt/core.h>

#include <memory>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/export/drop_deck_check.h"
#include "commands.h"

namespace bouncecal::apps {
namespace {

void RunExportCheck(const std::string& folder, double max_gravity_effect) {
  calibrate::DropDeckCheckOptions options;
  options.max_gravity_effect = max_gravity_effect;
  const auto check = calibrate::CheckDropDeckFolder(folder, options);
  fmt::print("{:>3} {:>11} {:>11} {:>9} {:>8} {:>10} {:>8} {:>8}  {}\n", "k", "v_in m/s",
             "v_out m/s", "e", "e dev %", "t_c s", "t_c dev%", "allow %", "verdict");
  for (size_t k = 0; k < check.bounces.size(); ++k) {
    const auto& b = check.bounces[k];
    fmt::print("{:>3} {:>11.5f} {:>11.5f} {:>9.6f} {:>+8.3f} {:>10.4g} {:>+8.3f} {:>8.3f}  {}\n",
               k + 1, b.bounce.impact_speed_mps, b.bounce.rebound_speed_mps, b.bounce.restitution,
               100 * b.restitution_deviation, b.bounce.contact_end_s - b.bounce.contact_start_s,
               100 * b.duration_deviation, 100 * b.allowed_deviation,
               !b.judged  ? "not judged (gravity during contact)"
               : b.within ? "ok"
                          : "MISMATCH");
  }
  if (check.unresolved_contacts > 0) {
    fmt::print("{} contact(s) could not be resolved from the output interval\n",
               check.unresolved_contacts);
  }
  fmt::print("{}: {} of {} judged bounces within the expected deviation\n",
             check.passed ? "PASSED" : "FAILED", check.within, check.judged);
  if (!check.passed) {
    throw CheckFailedError(folder +
                           ": the engine's trajectory misses the restitution or contact "
                           "duration the deck promised; see the table above");
  }
}

}  // namespace

void AddExportCheckCommand(CLI::App& app) {
  auto folder = std::make_shared<std::string>();
  auto max_gravity_effect =
      std::make_shared<double>(calibrate::DropDeckCheckOptions{}.max_gravity_effect);
  auto* command = app.add_subcommand(
      "export-check",
      "After running an exported single-drop deck: compare each bounce's restitution and contact "
      "duration in its trajectory.txt with what the deck promised (deck.json)");
  command
      ->add_option("deck", *folder, "Deck folder written by bouncecal export and run by the engine")
      ->required();
  command
      ->add_option("--max-gravity-effect", *max_gravity_effect,
                   "Judge only bounces where gravity during the contact, g t_c / v, is at most "
                   "this fraction (0, 1]")
      ->capture_default_str()
      ->check(CLI::Range(1e-9, 1.0));
  command->footer(
      "Example:\n"
      "  bouncecal export --material steel.json --engine lammps -o deck\n"
      "  (cd deck && lmp -in in.drop -log log.lammps)\n"
      "  bouncecal export-check deck");
  command->callback([folder, max_gravity_effect] { RunExportCheck(*folder, *max_gravity_effect); });
}

}  // namespace bouncecal::apps
