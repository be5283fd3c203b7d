#ifndef BOUNCECAL_EXPORT_SRC_DECK_TEXT_H_
#define BOUNCECAL_EXPORT_SRC_DECK_TEXT_H_

#include <fmt/core.h>

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/error.h"

// Text helpers shared by the deck writers.
namespace bouncecal::calibrate::deck_text {

// Enough digits that the engine reproduces the closed forms to far better than the 1e-3 the
// verification needs, few enough to stay readable.
inline std::string Number(double value) { return fmt::format("{:.12g}", value); }

inline void RequirePositive(double value, std::string_view name, std::string_view unit) {
  if (!std::isfinite(value) || !(value > 0)) {
    throw ConfigError(
        fmt::format("{} must be a positive finite number of {}, got {}", name, unit, value));
  }
}

// Comment lines wrapped at about 96 columns so the header reads well in any editor.
inline std::string CommentBlock(const std::vector<std::string>& lines) {
  constexpr size_t kWidth = 96;
  std::string text;
  for (const auto& line : lines) {
    std::string current = "#";
    size_t start = 0;
    bool first_word = true;
    while (start < line.size()) {
      size_t end = line.find(' ', start);
      if (end == std::string::npos) end = line.size();
      const std::string word = line.substr(start, end - start);
      if (!first_word && current.size() + 1 + word.size() > kWidth) {
        text += current + "\n";
        current = "#  ";
      }
      current += " " + word;
      first_word = false;
      start = end + 1;
    }
    text += current + "\n";
  }
  return text;
}

// Both engines can clip the dashpot's pull at the end of a contact; the decks must not.
inline std::string AttractiveTailNote(bool lammps) {
  return fmt::format(
      "{} is left off on purpose: the matched closed forms count the dashpot's attractive pull "
      "just before separation; switching it on raises e (bouncecal docs/physics.md section 4: "
      "0.64 -> 0.66).",
      lammps ? "limit_damping" : "limitForce");
}

}  // namespace bouncecal::calibrate::deck_text

#endif  // BOUNCECAL_EXPORT_SRC_DECK_TEXT_H_
