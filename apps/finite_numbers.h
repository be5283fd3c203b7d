#ifndef BOUNCECAL_APPS_FINITE_NUMBERS_H_
#define BOUNCECAL_APPS_FINITE_NUMBERS_H_

#include <CLI/CLI.hpp>

namespace bouncecal::apps {

// Throws a ConfigError naming the option when any numeric option given to the parsed command
// holds a value that is not a finite number ("nan", "inf", "1e999"). It runs once, before any
// command does its work, so that no command needs its own check: without it a range check
// downstream echoed "nan" back, and an option a command reads only in some modes passed
// unchecked.
void RefuseNonFiniteNumbers(const CLI::App& app);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_FINITE_NUMBERS_H_
