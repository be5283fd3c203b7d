#include "option_names.h"

#include <array>
#include <utility>

#include "bouncecal/option_error.h"

namespace bouncecal::apps {
namespace {

// Fields whose flag is not the field with dashes.
constexpr std::array<std::pair<std::string_view, std::string_view>, 2> kShortFlags{{
    {"first_n", "--first"},
    {"confidence_level", "--confidence"},
}};

}  // namespace

std::string FlagOf(std::string_view field) {
  for (const auto& [name, flag] : kShortFlags) {
    if (name == field) return std::string(flag);
  }
  std::string flag = "--";
  for (char c : field) flag += c == '_' ? '-' : c;
  return flag;
}

std::string WithFlags(std::string message, const std::vector<std::string>& fields) {
  return SpellFields(std::move(message), fields, FlagOf);
}

}  // namespace bouncecal::apps
