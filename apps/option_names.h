#ifndef BOUNCECAL_APPS_OPTION_NAMES_H_
#define BOUNCECAL_APPS_OPTION_NAMES_H_

#include <string>
#include <string_view>
#include <vector>

namespace bouncecal::apps {

// The command-line flag of an options field the libraries name in their messages
// (bouncecal/option_error.h): `drop_height_m` -> `--drop-height-m`. The flag is the field with
// dashes, except where the command line kept a shorter established name (first_n -> --first).
std::string FlagOf(std::string_view field);

// `message` with each option it names in backticks spelt as the flag with its value
// (bouncecal::SpellOptions: `first_n=3` -> --first 3). Everything the command prints or writes
// from the libraries passes through one of these.
std::string WithFlags(std::string_view message);

// The same for an OptionError: also each mention of its `fields` (bouncecal::SpellFields).
std::string WithFlags(std::string message, const std::vector<std::string>& fields);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_OPTION_NAMES_H_
