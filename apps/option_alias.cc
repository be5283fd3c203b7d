#include "option_alias.h"

#include <fmt/core.h>

#include "bouncecal/error.h"

namespace bouncecal::apps {

void NoteDeprecatedSpelling(const CLI::Option& canonical, const std::string& old_name,
                            bool& noted) {
  if (canonical.count() > 0) {
    throw ConfigError(fmt::format("{} and {} are one option ({} is its old spelling); give it once",
                                  canonical.get_name(), old_name, old_name));
  }
  for (const CLI::Option* excluded : canonical.get_excludes()) {
    if (excluded->count() > 0) {
      throw ConfigError(fmt::format("{} (old spelling of {}) excludes {}", old_name,
                                    canonical.get_name(), excluded->get_name()));
    }
  }
  if (noted) return;
  noted = true;
  fmt::print(stderr,
             "bouncecal: note: {} is deprecated and will be removed in the next release; use {}\n",
             old_name, canonical.get_name());
}

}  // namespace bouncecal::apps
