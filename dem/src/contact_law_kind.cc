#include "bouncecal/dem/contact_law_kind.h"

#include "bouncecal/error.h"

namespace bouncecal::dem {

std::string_view ToString(ContactLawKind kind) {
  switch (kind) {
    case ContactLawKind::kWaltonBraun:
      return "walton-braun";
    case ContactLawKind::kWaltonBraunPlastic:
      return "walton-braun-plastic";
    case ContactLawKind::kLinearDashpot:
      return "linear-dashpot";
    case ContactLawKind::kHertz:
      return "hertz";
    case ContactLawKind::kHertzViscoelastic:
      return "hertz-viscoelastic";
  }
  return "unknown";
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
