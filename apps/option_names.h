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

// `message` with each mention of `fields` spelt as its flag (bouncecal::SpellFields).
std::string WithFlags(std::string message, const std::vector<std::string>& fields);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_OPTION_NAMES_H_
