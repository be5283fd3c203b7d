#ifndef BOUNCECAL_APPS_SHELL_QUOTE_H_
#define BOUNCECAL_APPS_SHELL_QUOTE_H_

#include <string>

namespace bouncecal::apps {

// A POSIX shell single-quoted word, always quoted: a quote inside is closed, escaped and
// reopened. For commands pack runs (gnuplot) and prints (how to resume).
inline std::string SingleQuotedForShell(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_SHELL_QUOTE_H_
