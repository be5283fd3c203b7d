#ifndef BOUNCECAL_OPTION_ERROR_H_
#define BOUNCECAL_OPTION_ERROR_H_

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal {

// A ConfigError about fields of an options struct. The message spells each field as the library
// names it: a name with an underscore as it is (drop_height_m, first_n), a one-word name in
// backticks (`ball`, `channel`) so it is not mistaken for the word. Python's keywords are those
// names and the command line rewrites each into its flag (apps/option_names.h), both through
// SpellFields, so no library message names a flag and every front end names its own spelling.
class OptionError : public ConfigError {
 public:
  OptionError(std::vector<std::string> fields, const std::string& message)
      : ConfigError(message), fields_(std::move(fields)) {}

  const std::vector<std::string>& fields() const { return fields_; }

 private:
  std::vector<std::string> fields_;
};

// `message` with every mention of `fields` (a backticked `name`, and a name with an underscore
// as a whole word) replaced by spell(name).
std::string SpellFields(std::string message, const std::vector<std::string>& fields,
                        const std::function<std::string(std::string_view)>& spell);

// Spells an option for one front end: (field, value) -> text, where value is empty for the option
// alone. The command line writes `--first 3`, Python `first_n=3`.
using OptionSpeller = std::function<std::string(std::string_view field, std::string_view value)>;

// Every message the libraries write (errors, warnings, checks, notes) names an option the user
// can change in backticks, as the options struct names it: `compare_laws`, or with the value to
// give it, `objective=mean-energy-loss`, `first_n=3`. Returns `message` with each such mention
// replaced by spell(field, value); backticked text that is not a lower-case name is left alone.
// The front ends apply it to everything they show, so no library text carries a flag.
std::string SpellOptions(std::string_view message, const OptionSpeller& spell);

}  // namespace bouncecal

#endif  // BOUNCECAL_OPTION_ERROR_H_
