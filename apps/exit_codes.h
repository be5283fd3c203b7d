#ifndef BOUNCECAL_APPS_EXIT_CODES_H_
#define BOUNCECAL_APPS_EXIT_CODES_H_

namespace bouncecal::apps {

// Documented in README.md; scripts rely on them, so never renumber.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;     // a bug: please report it
inline constexpr int kExitInputFile = 2;    // an input file is missing, unreadable or malformed
inline constexpr int kExitBadOption = 3;    // an option or parameter is outside its valid range
inline constexpr int kExitOutputFile = 4;   // an output file could not be written
inline constexpr int kExitCheckFailed = 5;  // a verification ran and did not pass
inline constexpr int kExitInterrupted =
    6;  // stopped by SIGINT/SIGTERM; resumable from a checkpoint

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_EXIT_CODES_H_
