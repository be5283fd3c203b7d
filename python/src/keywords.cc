#include "keywords.h"

#include <array>
#include <cstdlib>
#include <string>

#include "bouncecal/option_error.h"

namespace bouncecal::python {
namespace {

// Options of the command line with no keyword in the module (ranking laws, plots, checkpoints,
// scene templates): named as the command's flag. Python plots with its own tools.
constexpr std::array<std::string_view, 7> kCommandLineOnly{
    "compare_laws", "laws", "plot", "template", "help", "checkpoint_every_s", "resume"};

bool IsNumber(std::string_view value) {
  const std::string text(value);
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size();
}

std::string Keyword(std::string_view field, std::string_view value) {
  if (field == "card") return "Calibration.write_card()";
  for (auto only : kCommandLineOnly) {
    if (field != only) continue;
    std::string text = "the command line's --";
    for (char c : field) text += c == '_' ? '-' : c;
    if (!value.empty()) text.append(" ").append(value);
    return text;
  }
  std::string keyword(field);
  if (value.empty()) return keyword;
  const std::string_view quote = IsNumber(value) ? "" : "'";
  keyword.append("=").append(quote).append(value).append(quote);
  return keyword;
}

}  // namespace

std::string WithKeywords(std::string_view message) { return SpellOptions(message, Keyword); }

}  // namespace bouncecal::python
