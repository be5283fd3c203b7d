#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "bouncecal/version.h"
#include "commands.h"
#include "exit_codes.h"
#include "finite_numbers.h"
#include "option_names.h"
#include "stop_signals.h"

namespace {

// Library messages name options in backticks; the command line shows them as flags.
int ReportError(const char* message, int status) {
  std::fprintf(stderr, "bouncecal: error: %s\n", bouncecal::apps::WithFlags(message).c_str());
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  namespace apps = bouncecal::apps;
  CLI::App app{
      "bouncecal: calibrate DEM contact damping from the sound of a bouncing ball.\n"
      "All quantities are SI (m, s, kg, N/m) unless an option name says otherwise."};
  app.require_subcommand(1);
  // `bouncecal --version` as other tools have it; `bouncecal version` prints the same line.
  app.set_version_flag("--version", "bouncecal " + std::string(bouncecal::Version()),
                       "Print the toolkit version and exit");
  apps::AddVersionCommand(app);
  apps::AddSimulateCommand(app);
  apps::AddCalibrateCommand(app);
  apps::AddSweepCommand(app);
  apps::AddCompareCommand(app);
  apps::AddSynthCommand(app);
  apps::AddAnalyzeCommand(app);
  apps::AddExportCommand(app);
  apps::AddExportCheckCommand(app);
  apps::AddPackCommand(app);
  apps::AddReportCommand(app);
  // Runs after parsing, before the command's own callback.
  app.parse_complete_callback([&app] { apps::RefuseNonFiniteNumbers(app); });

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& success) {
    return app.exit(success);
  } catch (const CLI::ParseError& error) {
    // CLI11 prints its own message; map every usage problem to one documented status.
    app.exit(error);
    return apps::kExitBadOption;
  } catch (const bouncecal::InputError& error) {
    return ReportError(error.what(), apps::kExitInputFile);
  } catch (const bouncecal::OptionError& error) {
    // The library names its fields; the command line speaks in flags.
    return ReportError(apps::WithFlags(error.what(), error.fields()).c_str(), apps::kExitBadOption);
  } catch (const bouncecal::ConfigError& error) {
    return ReportError(error.what(), apps::kExitBadOption);
  } catch (const bouncecal::OutputError& error) {
    return ReportError(error.what(), apps::kExitOutputFile);
  } catch (const bouncecal::CheckFailedError& error) {
    return ReportError(error.what(), apps::kExitCheckFailed);
  } catch (const apps::InterruptedError& error) {
    return ReportError(error.what(), apps::kExitInterrupted);
  } catch (const bouncecal::Error& error) {
    return ReportError(error.what(), apps::kExitBadOption);
  } catch (const std::bad_alloc&) {
    return ReportError(
        "out of memory; use a smaller input (a shorter recording, fewer particles) or a machine "
        "with more memory",
        apps::kExitInternal);
  } catch (const std::exception& error) {
    return ReportError(error.what(), apps::kExitInternal);
  }
  return apps::kExitOk;
}
