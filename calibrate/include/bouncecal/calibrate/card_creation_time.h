#ifndef BOUNCECAL_CALIBRATE_CARD_CREATION_TIME_H_
#define BOUNCECAL_CALIBRATE_CARD_CREATION_TIME_H_

#include <ctime>
#include <string_view>

namespace bouncecal::calibrate {

// The time a material card records: SOURCE_DATE_EPOCH when this process's environment sets it
// (the reproducible-builds convention, so two runs give byte-identical cards), otherwise now.
// A value that is not a whole number of seconds in 0 .. 253402300799 (year 9999) is a
// ConfigError, as the convention asks; its message ends with `remedy` (what the caller can do
// instead: the command line and Python offer different ways).
std::time_t CardCreationTimeFromEnvironment(std::string_view remedy);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_CARD_CREATION_TIME_H_
