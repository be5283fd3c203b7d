#include "bouncecal/dem/contact_law.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

template <std::size_t I = 0>
std::span<const ParameterSpec> SpecsOf(ContactLawKind kind) {
  if constexpr (I == std::variant_size_v<ContactLaw>) {
    throw ConfigError(fmt::format("contact law '{}' has no registered parameters; valid laws: {}",
                                  ToString(kind), ContactLawNames()));
  } else {
    using Law = std::variant_alternative_t<I, ContactLaw>;
    if (kKindOf<Law> == kind) return Law::Specs();
    return SpecsOf<I + 1>(kind);
  }
}

template <std::size_t I = 0>
ContactLaw Make(const ContactLawConfig& config) {
  if constexpr (I == std::variant_size_v<ContactLaw>) {
    throw ConfigError(fmt::format("contact law '{}' cannot be built; valid laws: {}",
                                  ToString(config.kind), ContactLawNames()));
  } else {
    using Law = std::variant_alternative_t<I, ContactLaw>;
    if (kKindOf<Law> == config.kind)
      return ContactLaw(std::in_place_type<Law>, Law::FromConfig(config));
    return Make<I + 1>(config);
  }
}

const ParameterSpec* FindSpec(ContactLawKind kind, std::string_view name) {
  for (const ParameterSpec& spec : ParameterSpecs(kind)) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

std::string SpecNames(ContactLawKind kind) {
  std::string names;
  for (const ParameterSpec& spec : ParameterSpecs(kind)) {
    if (!names.empty()) names += ", ";
    names += spec.name;
  }
  return names;
}

}  // namespace

std::span<const ParameterSpec> ParameterSpecs(ContactLawKind kind) { return SpecsOf(kind); }

void CheckParameterValue(const ParameterSpec& spec, double value, std::string_view context) {
  if (std::isfinite(value) && value >= spec.min_value && value <= spec.max_value) return;
  throw ConfigError(fmt::format(
      "{} parameter {} = {} is outside its valid range [{:g}, {:g}]{}{}; choose a finite value "
      "in that range",
      context, spec.name, value, spec.min_value, spec.max_value, spec.unit == "1" ? "" : " ",
      spec.unit == "1" ? "" : spec.unit));
}

double ContactLawConfig::Get(std::string_view name) const {
  const ParameterSpec* spec = FindSpec(kind, name);
  if (spec == nullptr) {
    throw ConfigError(fmt::format("contact law {} has no parameter '{}'; its parameters are: {}",
                                  ToString(kind), name, SpecNames(kind)));
  }
  const auto found = parameters.find(name);
  return found == parameters.end() ? spec->default_value : found->second;
}

void ContactLawConfig::Validate() const {
  for (const auto& [name, value] : parameters) {
    const ParameterSpec* spec = FindSpec(kind, name);
    if (spec == nullptr) {
      throw ConfigError(fmt::format("contact law {} has no parameter '{}'; its parameters are: {}",
                                    ToString(kind), name, SpecNames(kind)));
    }
    CheckParameterValue(*spec, value, ToString(kind));
  }
}

ContactLaw MakeContactLaw(const ContactLawConfig& config) {
  config.Validate();
  return Make(config);
}

ContactLawKind KindOf(const ContactLaw& law) { return static_cast<ContactLawKind>(law.index()); }

bool SupportsExactImpacts(const ContactLaw& law) {
  return std::visit([](const auto& typed) { return HasExactImpact<std::decay_t<decltype(typed)>>; },
                    law);
}

std::string ExactImpactLawNames() {
  std::string names;
  for (ContactLawKind kind : kAllContactLawKinds) {
    if (!SupportsExactImpacts(Make(ContactLawConfig{.kind = kind, .parameters = {}}))) continue;
    if (!names.empty()) names += ", ";
    names += ToString(kind);
  }
  return names;
}

EngineForm ExportFormOf(const ContactLaw& law) {
  return std::visit(
      [](const auto& typed) -> EngineForm {
        if constexpr (HasEngineForm<std::decay_t<decltype(typed)>>) {
          return typed.ExportForm();
        } else {
          return EngineMatchAtSpeed{};
        }
      },
      law);
}

std::optional<double> ClosedFormRestitutionOf(const ContactLaw& law, double effective_mass_kg,
                                              double effective_radius_m, double impact_speed_mps) {
  return std::visit(
      [&](const auto& typed) {
        return typed.ClosedFormRestitution(effective_mass_kg, effective_radius_m, impact_speed_mps);
      },
      law);
}

std::optional<double> ClosedFormContactDurationOf(const ContactLaw& law, double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps) {
  return std::visit(
      [&](const auto& typed) {
        return typed.ClosedFormContactDuration(effective_mass_kg, effective_radius_m,
                                               impact_speed_mps);
      },
      law);
}

}  // namespace bouncecal::dem
