#include "bouncecal/option_error.h"

#include <algorithm>
#include <cctype>

namespace bouncecal {
namespace {

bool IsWordCharacter(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Replaces each occurrence of `pattern` in `text` that `accept(begin, end)` approves.
template <typename Accept>
void ReplaceAll(std::string& text, const std::string& pattern, const std::string& replacement,
                Accept accept) {
  for (std::size_t at = text.find(pattern); at != std::string::npos; at = text.find(pattern, at)) {
    if (accept(at, at + pattern.size())) {
      text.replace(at, pattern.size(), replacement);
      at += replacement.size();
    } else {
      at += pattern.size();
    }
  }
}

}  // namespace

std::string SpellFields(std::string message, const std::vector<std::string>& fields,
                        const std::function<std::string(std::string_view)>& spell) {
  for (const auto& field : fields) {
    const std::string spelt = spell(field);
    ReplaceAll(message, "`" + field + "`", spelt, [](std::size_t, std::size_t) { return true; });
    if (field.find('_') == std::string::npos) continue;
    ReplaceAll(message, field, spelt, [&message](std::size_t begin, std::size_t end) {
      return (begin == 0 || !IsWordCharacter(message[begin - 1])) &&
             (end == message.size() || !IsWordCharacter(message[end]));
    });
  }
  return message;
}

std::string SpellOptions(std::string_view message, const OptionSpeller& spell) {
  std::string spelt;
  spelt.reserve(message.size());
  std::size_t copied = 0;
  for (std::size_t open = message.find('`'); open != std::string_view::npos;
       open = message.find('`', open + 1)) {
    const std::size_t close = message.find('`', open + 1);
    if (close == std::string_view::npos) break;
    const std::string_view inside = message.substr(open + 1, close - open - 1);
    const std::size_t equals = inside.find('=');
    const std::string_view field = inside.substr(0, equals);
    const std::string_view value =
        equals == std::string_view::npos ? std::string_view() : inside.substr(equals + 1);
    const bool is_name = !field.empty() && std::islower(static_cast<unsigned char>(field[0])) &&
                         std::all_of(field.begin(), field.end(), [](char c) {
                           return std::islower(static_cast<unsigned char>(c)) ||
                                  std::isdigit(static_cast<unsigned char>(c)) || c == '_';
                         });
    if (is_name && !(equals != std::string_view::npos && value.empty())) {
      spelt.append(message.substr(copied, open - copied));
      spelt += spell(field, value);
      copied = close + 1;
    }
    open = close;  // a closing backtick never opens the next mention
  }
  spelt.append(message.substr(copied));
  return spelt;
}

}  // namespace bouncecal
