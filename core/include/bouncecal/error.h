#ifndef BOUNCECAL_ERROR_H_
#define BOUNCECAL_ERROR_H_

#include <stdexcept>
#include <string>
#include <string_view>

namespace bouncecal {

// Every problem a user can fix (a bad file, an out-of-range parameter, an unwritable output) is
// reported as an Error whose message is one line: what went wrong, which file or value, and what
// to do. Programmer invariants use assert instead; numerical non-convergence goes into a Summary.
// The constructor escapes control characters, so a newline inside a user's file name, a JSON
// key or a string value quoted back in the message cannot break the one-line promise.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(OneLine(message)) {}
  explicit Error(const char* message) : Error(std::string(message)) {}

  // "\n" for a newline, "\t" for a tab, "\xNN" for any other control character.
  static std::string OneLine(std::string_view text);
};

// An input file that cannot be read or does not hold what it should (exit status 2 in the CLI).
class InputError : public Error {
 public:
  using Error::Error;
};

// A parameter or configuration value outside its valid range (exit status 3 in the CLI).
class ConfigError : public Error {
 public:
  using Error::Error;
};

// An output that cannot be written (exit status 4 in the CLI).
class OutputError : public Error {
 public:
  using Error::Error;
};

// A check the user asked for ran and did not pass, e.g. an exported deck whose trajectory misses
// the card's restitution (exit status 5 in the CLI, so scripts can tell it from bad input).
class CheckFailedError : public Error {
 public:
  using Error::Error;
};

}  // namespace bouncecal

#endif  // BOUNCECAL_ERROR_H_
