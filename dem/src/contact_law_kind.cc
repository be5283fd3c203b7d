#include "bouncecal/dem/contact_law_kind.h"

#include <cstddef>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {

std::string_view ToString(ContactLawKind kind) {
  const auto index = static_cast<std::size_t>(kind);
  return index < kContactLawNames.size() ? kContactLawNames[index] : "unknown";
}

std::string ContactLawNames() {
  std::string names;
  for (ContactLawKind kind : kAllContactLawKinds) {
    if (!names.empty()) names += ", ";
    names += ToString(kind);
  }
  return names;
}

ContactLawKind ContactLawKindFromString(std::string_view name) {
  for (ContactLawKind kind : kAllContactLawKinds) {
    if (ToString(kind) == name) return kind;
  }
  throw ConfigError("unknown contact law '" + std::string(name) +
                    "'; valid laws: " + ContactLawNames());
}

}  // namespace bouncecal::dem
