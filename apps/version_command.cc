#include <fmt/core.h>

#include "bouncecal/version.h"
#include "commands.h"

namespace bouncecal::apps {

void AddVersionCommand(CLI::App& app) {
  auto* command = app.add_subcommand("version", "Print the toolkit version");
  command->footer("Example:\n  bouncecal version");
  command->callback([] { fmt::print("bouncecal {}\n", Version()); });
}

}  // namespace bouncecal::apps
