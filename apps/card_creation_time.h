#ifndef BOUNCECAL_APPS_CARD_CREATION_TIME_H_
#define BOUNCECAL_APPS_CARD_CREATION_TIME_H_

#include <ctime>

namespace bouncecal::apps {

// The time a material card records: SOURCE_DATE_EPOCH when this process's environment sets it
// (the reproducible-builds convention, so two runs give byte-identical cards), otherwise now.
// A value that is not a whole number of seconds in 0 .. 253402300799 (year 9999) is a
// ConfigError, as the convention asks.
std::time_t CardCreationTimeFromEnvironment();

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_CARD_CREATION_TIME_H_
