#include "option_names.h"

#include <array>
#include <utility>

#include "bouncecal/option_error.h"

namespace bouncecal::apps {
namespace {

// Fields whose flag is not the field with dashes.
constexpr std::array<std::pair<std::string_view, std::string_view>, 3> kShortFlags{{
    {"first_n", "--first"},
    {"confidence_level", "--confidence"},
    {"parameters", "--param"},
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

std::string WithFlags(std::string_view message) {
  return SpellOptions(message, [](std::string_view field, std::string_view value) {
    std::string flag = FlagOf(field);
    if (!value.empty()) flag.append(" ").append(value);
    return flag;
  });
}

std::string WithFlags(std::string message, const std::vector<std::string>& fields) {
  return WithFlags(SpellFields(std::move(message), fields, FlagOf));
}

}  // namespace bouncecal::apps
