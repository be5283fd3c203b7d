#ifndef BOUNCECAL_APPS_OPTION_ALIAS_H_
#define BOUNCECAL_APPS_OPTION_ALIAS_H_

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

namespace bouncecal::apps {

// The spelling a deprecated option's note asks for, printed on stderr as one line the first time
// the old spelling is used. Throws ConfigError when the canonical spelling or an option it
// excludes was given as well (the same quantity twice).
void NoteDeprecatedSpelling(const CLI::Option& canonical, const std::string& old_name, bool& noted);

// Registers old_name as a hidden spelling of `canonical`, kept for one release after a rename:
// it writes the same variable and prints the deprecation note on use. Not shown in --help, and
// not listed in the canonical option's "Excludes" (that would show the old name again); the clash
// is checked when the values are stored instead. Validators of the canonical option are not
// copied: add them to the returned option.
template <typename T>
CLI::Option* AddDeprecatedAlias(CLI::App& command, CLI::Option* canonical,
                                const std::string& old_name, T& variable) {
  auto noted = std::make_shared<bool>(false);
  auto* alias = command.add_option(old_name, variable, "Old spelling of " + canonical->get_name());
  alias->group("");
  alias->each([canonical, old_name, noted](const std::string&) {
    NoteDeprecatedSpelling(*canonical, old_name, *noted);
  });
  return alias;
}

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_OPTION_ALIAS_H_
