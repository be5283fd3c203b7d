#include "bouncecal/option_error.h"

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

}  // namespace bouncecal
