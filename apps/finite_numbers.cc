#include "finite_numbers.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

#include "bouncecal/error.h"

namespace bouncecal::apps {
namespace {

// CLI11 names a floating-point option's type "FLOAT" (also for optionals and vectors of
// them); every other type is a count, a name or a path, where "inf" may be a file name.
bool TakesFloatingPoint(const CLI::Option& option) {
  return std::string_view(option.get_type_name()).starts_with("FLOAT");
}

bool IsNonFiniteNumber(const std::string& text) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && !std::isfinite(value);
}

void RefuseInCommand(const CLI::App& command) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0 || !TakesFloatingPoint(*option)) continue;
    for (const std::string& text : option->results()) {
      if (!IsNonFiniteNumber(text)) continue;
      throw ConfigError(fmt::format("{} {}: not a finite number; give a finite value in its unit",
                                    option->get_name(), text));
    }
  }
  for (const CLI::App* subcommand : command.get_subcommands()) RefuseInCommand(*subcommand);
}

}  // namespace

void RefuseNonFiniteNumbers(const CLI::App& app) { RefuseInCommand(app); }

}  // namespace bouncecal::apps
