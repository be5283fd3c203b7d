#ifndef BOUNCECAL_APPS_COMMANDS_H_
#define BOUNCECAL_APPS_COMMANDS_H_

#include <CLI/CLI.hpp>

namespace bouncecal::apps {

// Each subcommand lives in its own file and registers itself on the top-level app. The callback
// does the work and throws bouncecal::Error subclasses for problems the user can fix; main()
// turns them into one-line messages and exit statuses.
void AddVersionCommand(CLI::App& app);
// simulate drop: the DEM single-ball drop (apps/simulate_command.cc).
void AddSimulateCommand(CLI::App& app);
void AddCalibrateCommand(CLI::App& app);
void AddSweepCommand(CLI::App& app);
void AddCompareCommand(CLI::App& app);
void AddSynthCommand(CLI::App& app);
void AddAnalyzeCommand(CLI::App& app);
// pack: multi-particle packing scenes (apps/pack_command.cc).
void AddPackCommand(CLI::App& app);
// export / export-check: LAMMPS and LIGGGHTS decks for a material card, and their verification
// (apps/export_command.cc, apps/export_check_command.cc).
void AddExportCommand(CLI::App& app);
void AddExportCheckCommand(CLI::App& app);
// report: calibration as one self-contained HTML page (apps/report_command.cc).
void AddReportCommand(CLI::App& app);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_COMMANDS_H_
